#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <cmath>
#include <dhdr/tonemap/reinhard.h>

namespace dhdr {

ReinhardMapping resolveReinhard(const LuminanceStats& stats, const ReinhardParams& params) {
    ReinhardMapping m;
    // L = α · Lw / L̄w (eq. 2), with the exposure as a further factor 2^stops.
    const double logAverage = stats.logAverage > 0.0 ? stats.logAverage : 1.0;
    m.scale = std::exp2(params.exposure) * params.key / logAverage;
    if (params.white > 0.0)
        m.white = params.white;
    else
        m.white = stats.maxLuminance > 0.0 ? m.scale * stats.maxLuminance
                                           : std::numeric_limits<double>::infinity();
    return m;
}

bool reinhard(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const ReinhardParams& params,
              OIIO::ROI roi, int nthreads) {
    if (!detail::prepareFloatDst(dst, src, roi, 3)) return false;
    LuminanceStats measured;
    const LuminanceStats* stats = params.stats;
    if (!stats) {
        computeLuminanceStats(measured, src, params.metering, {}, nthreads);
        stats = &measured;
    }
    const ReinhardMapping m = resolveReinhard(*stats, params);
    const LuminanceWeights w = params.metering.weights;

    const detail::FloatPixels in(src);
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float* p = in.at(x, y);
                float* q = detail::floatPixel(dst, x, y);
                const double Lw = luminance(p[0], p[1], p[2], w);
                // Colour scaled by Ld / Lw keeps the chromaticity (the paper maps luminance).
                const double ratio = Lw > 0.0 ? reinhardCurve(m.scale * Lw, m.white) / Lw : 0.0;
                for (int c = 0; c < 3; ++c)
                    q[c] = float(double(p[c]) * ratio);
                for (int c = 3; c < r.chend; ++c)
                    q[c] = p[c];
            }
    });
    return true;
}

} // namespace dhdr
