// Metering: the one luminance a tone-map operator maps to its key.
#pragma once

#include <dhdr/common/param_table.h>
#include <dhdr/tonemap/luminance.h>
#include <vector>

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

// Empty when `params`' percentiles are a window, 0 ≤ low < high ≤ 100; else why not, naming
// dhdr-tonemap's --percentiles or the Python keyword percentiles.
std::string percentilesProblem(const MeteringParams& params, Spelling spelling);

// meter() over an image that arrives strip by strip, rows in order, in passes: every row to
// add(), then endPass(), again while needsAnotherPass() (log-average metering takes one pass;
// histogram metering three: statistics, histogram, the sum between the percentiles). Each
// pass combines per-row sums in row order, so the result equals meter()'s bit for bit.
class MeteringAccumulator {
public:
    explicit MeteringAccumulator(const MeteringParams& params = {});
    // Rows `roi` of `src` (default: all of it), after every row above them in this pass.
    bool add(const OIIO::ImageBuf& src, OIIO::ROI roi = {}, int nthreads = 0);
    void endPass();
    bool needsAnotherPass() const;
    LuminanceStats result() const { return m_stats; }

private:
    MeteringParams m_params;
    int m_pass = 0;
    LuminanceAccumulator m_luminance;
    LuminanceStats m_stats;
    std::vector<long long> m_histogram;
    double m_lo = 0.0, m_binWidth = 1.0;
    int m_first = 0, m_last = 0; // bins of the two percentiles
    double m_sum = 0.0;
    long long m_count = 0;
};

// Luminance statistics as computeLuminanceStats gives them, with `logAverage` metered as
// `params.mode` says. Thread-count independent (integer histograms, per-row double sums).
bool meter(LuminanceStats& stats, const OIIO::ImageBuf& src, const MeteringParams& params = {},
           OIIO::ROI roi = {}, int nthreads = 0);

} // namespace dhdr
