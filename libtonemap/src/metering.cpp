#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/tonemap/metering.h>
#include <mutex>
#include <vector>

namespace dhdr {

namespace {

constexpr int kBins = 4096;

} // namespace

bool meter(LuminanceStats& stats, const OIIO::ImageBuf& src, const MeteringParams& params,
           OIIO::ROI roi, int nthreads) {
    if (!computeLuminanceStats(stats, src, params.luminance, roi, nthreads)) return false;
    if (params.mode == MeteringMode::LogAverage || stats.pixels == 0) return true;
    if (!roi.defined()) roi = src.roi();
    roi = OIIO::roi_intersection(roi, src.roi());

    // Histogram of ln(δ + Lw) between the extremes; bins are integers, so merging the
    // per-chunk histograms in any order gives the same counts.
    const LuminanceStatsParams& lp = params.luminance;
    const double lo = std::log(lp.delta + std::max(stats.minLuminance, 0.0));
    const double hi = std::log(lp.delta + stats.maxLuminance);
    const double binWidth = std::max(hi - lo, 1e-12) / kBins;
    const bool skipTransparent = lp.skipTransparent && src.nchannels() >= 4;
    const detail::FloatPixels pixels(src);
    // ln(δ + Lw) of a pixel that is metered, NaN for one that is not.
    auto logLuminance = [&](int x, int y) {
        const float* p = pixels.at(x, y);
        if (skipTransparent && p[3] == 0.0f) return double(NAN);
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            return double(NAN);
        return std::log(lp.delta + std::max(0.0, double(luminance(p[0], p[1], p[2], lp.weights))));
    };
    auto binOf = [&](double v) { return std::clamp(int((v - lo) / binWidth), 0, kBins - 1); };

    std::vector<long long> histogram(kBins, 0);
    std::mutex merge;
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        std::vector<long long> local(kBins, 0);
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const double v = logLuminance(x, y);
                if (!std::isnan(v)) ++local[size_t(binOf(v))];
            }
        std::lock_guard<std::mutex> lock(merge);
        for (int b = 0; b < kBins; ++b)
            histogram[size_t(b)] += local[size_t(b)];
    });

    // The bins holding the two percentiles; whole bins between them are metered.
    auto binAt = [&](double percentile) {
        const long long target = (long long)std::floor(percentile / 100.0 * double(stats.pixels));
        long long seen = 0;
        for (int b = 0; b < kBins; ++b) {
            seen += histogram[size_t(b)];
            if (seen > target) return b;
        }
        return kBins - 1;
    };
    const int first = binAt(params.lowPercentile), last = binAt(params.highPercentile);

    struct Row {
        double sum = 0.0;
        long long count = 0;
    };
    std::vector<Row> rows(static_cast<size_t>(roi.height()));
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y) {
            Row& row = rows[size_t(y - roi.ybegin)];
            for (int x = r.xbegin; x < r.xend; ++x) {
                const double v = logLuminance(x, y);
                if (std::isnan(v)) continue;
                const int b = binOf(v);
                if (b < first || b > last) continue;
                row.sum += v;
                ++row.count;
            }
        }
    });
    Row total;
    for (const Row& row : rows) {
        total.sum += row.sum;
        total.count += row.count;
    }
    if (total.count > 0) stats.logAverage = std::exp(total.sum / double(total.count));
    return true;
}

} // namespace dhdr
