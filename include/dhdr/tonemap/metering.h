// Metering: the one luminance a tone-map operator maps to its key.
#pragma once

#include <dhdr/tonemap/luminance.h>

namespace dhdr {

enum class MeteringMode {
    LogAverage, // exp(mean ln(δ + Lw)) over every metered pixel (Reinhard et al. 2002)
    Histogram,  // the same over the pixels between two percentiles of luminance only
};

struct MeteringParams {
    MeteringMode mode = MeteringMode::LogAverage;
    LuminanceStatsParams luminance;
    // Histogram metering: pixels below the low or above the high percentile of luminance
    // (specular highlights, light sources, black borders) are left out.
    double lowPercentile = 5.0;
    double highPercentile = 95.0;
};

// Luminance statistics as computeLuminanceStats gives them, with `logAverage` metered as
// `params.mode` says. Thread-count independent (integer histograms, per-row double sums).
bool meter(LuminanceStats& stats, const OIIO::ImageBuf& src, const MeteringParams& params = {},
           OIIO::ROI roi = {}, int nthreads = 0);

} // namespace dhdr
