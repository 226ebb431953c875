#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/tonemap/luminance.h>
#include <limits>
#include <vector>

namespace dhdr {

bool LuminanceAccumulator::add(const OIIO::ImageBuf& src, OIIO::ROI roi, int nthreads) {
    if (!src.initialized() || src.nchannels() < 3) return false;
    if (!roi.defined()) roi = src.roi();
    roi = OIIO::roi_intersection(roi, src.roi());
    if (roi.npixels() == 0) return true;

    const detail::FloatPixels pixels(src);
    const bool skipTransparent = m_params.skipTransparent && src.nchannels() >= 4;
    // Per-row partial sums, combined in row order so the result is thread-count independent.
    std::vector<Row> rows(static_cast<size_t>(roi.height()));
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y) {
            Row& row = rows[size_t(y - roi.ybegin)];
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
                double Lw = luminance(p[0], p[1], p[2], m_params.weights);
                if (Lw < 0.0) {
                    ++row.negative;
                    Lw = 0.0;
                }
                row.sumLog += std::log(m_params.delta + Lw);
                row.maxL = std::max(row.maxL, Lw);
                row.minL = std::min(row.minL, Lw);
                ++row.pixels;
            }
        }
    });
    for (const Row& row : rows) {
        m_total.sumLog += row.sumLog;
        m_total.maxL = std::max(m_total.maxL, row.maxL);
        m_total.minL = std::min(m_total.minL, row.minL);
        m_total.pixels += row.pixels;
        m_total.negative += row.negative;
        m_total.nonFinite += row.nonFinite;
        m_total.transparent += row.transparent;
    }
    return true;
}

LuminanceStats LuminanceAccumulator::result() const {
    LuminanceStats stats;
    stats.pixels = m_total.pixels;
    stats.negativePixels = m_total.negative;
    stats.nonFinitePixels = m_total.nonFinite;
    stats.transparentPixels = m_total.transparent;
    if (m_total.pixels > 0) {
        stats.logAverage = std::exp(m_total.sumLog / double(m_total.pixels));
        stats.maxLuminance = m_total.maxL;
        stats.minLuminance = m_total.minL;
    }
    return stats;
}

bool computeLuminanceStats(LuminanceStats& stats, const OIIO::ImageBuf& src,
                           const LuminanceStatsParams& params, OIIO::ROI roi, int nthreads) {
    stats = {};
    LuminanceAccumulator accumulator(params);
    if (!accumulator.add(src, roi, nthreads)) return false;
    stats = accumulator.result();
    return true;
}

} // namespace dhdr
