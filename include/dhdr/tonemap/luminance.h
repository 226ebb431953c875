// Luminance of linear RGB and its image statistics (the metering of the tone-map stage).
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/common/param_table.h>
#include <limits>

namespace dhdr {

// Weights of R, G, B in the luminance sum.
struct LuminanceWeights {
    float r, g, b;
};

// The seeds' weights (Reinhard et al. 2002 use these for their images).
inline constexpr LuminanceWeights kSeedLuminanceWeights{0.27f, 0.67f, 0.06f};
// ITU-R BT.709 / sRGB primaries.
inline constexpr LuminanceWeights kRec709LuminanceWeights{0.2126f, 0.7152f, 0.0722f};

inline float luminance(float r, float g, float b, LuminanceWeights w) {
    return w.r * r + w.g * g + w.b * b;
}

struct LuminanceStatsParams {
    LuminanceWeights weights = kSeedLuminanceWeights;
    // δ of the log-average, which keeps black pixels from sending it to zero.
    double delta = 1e-4;
    // Leave out pixels whose alpha (channel 3, when there is one) is 0: where a render has no
    // surface there is nothing to meter, and black would drag the log-average down.
    bool skipTransparent = true;
};

// LuminanceStatsParams' δ, and the option of dhdr-tonemap and keyword of the Python metering
// calls that set it.
inline constexpr FloatParam<LuminanceStatsParams, double> kLuminanceFloatTable[] = {
    {"--delta",
     "delta",
     &LuminanceStatsParams::delta,
     {0.0, 1.0, true},
     "D",
     "δ of the log-average"},
};

struct LuminanceStats {
    // exp(mean ln(δ + Lw)), Reinhard et al. 2002 eq. 1 (natural log and exp, consistently).
    double logAverage = 0.0;
    double maxLuminance = 0.0;
    double minLuminance = 0.0;
    long long pixels = 0;
    // Pixels whose luminance was negative; they are metered as 0.
    long long negativePixels = 0;
    // Pixels with a NaN or infinite channel; they are left out of every statistic.
    long long nonFinitePixels = 0;
    // Pixels left out for alpha = 0 (LuminanceStatsParams::skipTransparent).
    long long transparentPixels = 0;
};

// computeLuminanceStats over an image that arrives strip by strip, rows in order: the same
// per-row sums combined in the same order, so the result equals the whole image's bit for
// bit.
class LuminanceAccumulator {
public:
    explicit LuminanceAccumulator(const LuminanceStatsParams& params = {}) : m_params(params) {}
    // Rows `roi` of `src` (default: all of it), after every row above them.
    bool add(const OIIO::ImageBuf& src, OIIO::ROI roi = {}, int nthreads = 0);
    LuminanceStats result() const;

private:
    struct Row {
        double sumLog = 0.0;
        double maxL = -std::numeric_limits<double>::infinity();
        double minL = std::numeric_limits<double>::infinity();
        long long pixels = 0, negative = 0, nonFinite = 0, transparent = 0;
    };

    LuminanceStatsParams m_params;
    Row m_total;
};

// Luminance statistics of the first three channels of `src` over `roi`. The sums are
// accumulated per row in double and added in row order, so the result does not depend on
// the thread count. Returns false when `src` is empty or has fewer than three channels.
bool computeLuminanceStats(LuminanceStats& stats, const OIIO::ImageBuf& src,
                           const LuminanceStatsParams& params = {}, OIIO::ROI roi = {},
                           int nthreads = 0);

} // namespace dhdr
