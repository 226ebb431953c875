// Eye adaptation over a sequence: the luminance the eye is adapted to follows the metered
// luminance with a lag.
#pragma once

#include <dhdr/common/param_table.h>
#include <vector>

namespace dhdr {

struct AdaptationParams {
    double fps = 24.0;
    // The seed's adapted += (L − adapted)(1 − rate^(speed·dt)): with rate 0.98 and speed 30 the
    // eye closes 2 % of the gap per 1/30 s.
    double rate = 0.98;
    double speed = 30.0;
};

// AdaptationParams' ranges, and the options of dhdr-tonemap and keywords of dhdr.adapt() and
// dhdr.adapt_luminance() that set them.
inline constexpr FloatParam<AdaptationParams, double> kAdaptationFloatTable[] = {
    {"--fps",
     "fps",
     &AdaptationParams::fps,
     {0.0, 1000.0, true},
     "N",
     "frames per second of the sequence, dt = 1/fps"},
    {"--adapt-rate",
     "rate",
     &AdaptationParams::rate,
     {0.0, 1.0},
     "R",
     "the adaptation's base: each frame closes 1 - R^(speed/fps) of the gap to the frame's "
     "luminance (1: never adapts, 0: at once)"},
    {"--adapt-speed",
     "speed",
     &AdaptationParams::speed,
     {0.0, 1000.0, true},
     "S",
     "the adaptation's speed, per second (the eye closes 1 - R of the gap every 1/S s)"},
};

// The adapted luminance of each frame, starting adapted to the first: a sequential scan over
// the per-frame metered luminances (which may be computed in any order or in parallel).
std::vector<double> adaptLuminance(const std::vector<double>& metered,
                                   const AdaptationParams& params = {});

} // namespace dhdr
