// The sun of an environment: the few texels of a sunny sky that hold most of its light, split
// off as a directional light with an angular diameter, so that its shadows and highlights are
// a light's, exact, rather than what samples or prefiltered levels make of a few texels.
#pragma once

#include <dhdr/deferred/environment/environment.h>
#include <glm/glm.hpp>

namespace dhdr {

struct EnvironmentSun {
    glm::vec3 direction{0.0f, 1.0f, 0.0f}; // unit, towards the sun, in the environment's frame
    float angle = 0.0f;                    // angular diameter, radians
    // ∫ (L − L_sky) dω over the sun, per channel: the illuminance it gives a surface facing it,
    // in the image's units × sr.
    glm::vec3 illuminance{0.0f};
    double share = 0.0;     // of the environment's luminance power, ∫ Y dω, in [0, 1]
    float threshold = 0.0f; // the luminance it was split at

    bool found() const { return illuminance != glm::vec3(0.0f); }
};

// Luminance (Rec. 709 weights) above which a texel is sun: as Blender EEVEE's world "Sun
// Threshold" (default 10), in the image's units.
inline constexpr float kDefaultSunThreshold = 10.0f;
// A bright region wider than this (radians, 20°) is bright sky, a window or a lamp, not a sun:
// it is left in the environment.
inline constexpr float kMaxSunAngle = 0.3490659f;

// Splits the sun off `env`: the region of texels brighter than `threshold` (luminance) around
// the brightest texel, connected (8-neighbours, wrapping around in longitude). Each of its
// texels keeps `threshold` of luminance, in its own chroma, and gives the rest to the sun, so
// that the sun and the sky left add up to the environment texel by texel. The sun's direction
// is the mean of the texels' directions weighted by what they gave (luminance × solid angle);
// its angle the diameter of the disk with the same spread (for a uniform disk of angular
// radius r, the mean squared angle from its centre is r²/2), at least one texel. Nothing
// changes, and the result is not found(), when no texel is above `threshold`, `threshold` is
// not positive, or the region is wider than kMaxSunAngle.
EnvironmentSun extractSun(EnvironmentImage& env, float threshold);

} // namespace dhdr
