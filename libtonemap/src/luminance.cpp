#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/tonemap/luminance.h>
#include <limits>
#include <vector>

namespace dhdr {

namespace {

// Per-row partial sums, combined in row order so the result is thread-count independent.
struct RowStats {
    double sumLog = 0.0;
    double maxL = -std::numeric_limits<double>::infinity();
    double minL = std::numeric_limits<double>::infinity();
    long long pixels = 0, negative = 0, nonFinite = 0, transparent = 0;
};

} // namespace

bool computeLuminanceStats(LuminanceStats& stats, const OIIO::ImageBuf& src,
                           const LuminanceStatsParams& params, OIIO::ROI roi, int nthreads) {
    stats = {};
    if (!src.initialized() || src.nchannels() < 3) return false;
    if (!roi.defined()) roi = src.roi();
    roi = OIIO::roi_intersection(roi, src.roi());
    if (roi.npixels() == 0) return true;

    const detail::FloatPixels pixels(src);
    const bool skipTransparent = params.skipTransparent && src.nchannels() >= 4;
    std::vector<RowStats> rows(static_cast<size_t>(roi.height()));
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y) {
            RowStats& row = rows[size_t(y - roi.ybegin)];
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float* p = pixels.at(x, y);
                if (skipTransparent && p[3] == 0.0f) {
                    ++row.transparent;
                    continue;
                }
                if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
                    ++row.nonFinite;
                    continue;
                }
                double Lw = luminance(p[0], p[1], p[2], params.weights);
                if (Lw < 0.0) {
                    ++row.negative;
                    Lw = 0.0;
                }
                row.sumLog += std::log(params.delta + Lw);
                row.maxL = std::max(row.maxL, Lw);
                row.minL = std::min(row.minL, Lw);
                ++row.pixels;
            }
        }
    });

    RowStats total;
    for (const RowStats& row : rows) {
        total.sumLog += row.sumLog;
        total.maxL = std::max(total.maxL, row.maxL);
        total.minL = std::min(total.minL, row.minL);
        total.pixels += row.pixels;
        total.negative += row.negative;
        total.nonFinite += row.nonFinite;
        total.transparent += row.transparent;
    }
    stats.pixels = total.pixels;
    stats.negativePixels = total.negative;
    stats.nonFinitePixels = total.nonFinite;
    stats.transparentPixels = total.transparent;
    if (total.pixels > 0) {
        stats.logAverage = std::exp(total.sumLog / double(total.pixels));
        stats.maxLuminance = total.maxL;
        stats.minLuminance = total.minL;
    }
    return true;
}

} // namespace dhdr
