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
    LuminanceStats measured;
    const LuminanceStats* stats = params.stats;
    if (!stats) {
        computeLuminanceStats(measured, src, params.metering, {}, nthreads);
        stats = &measured;
    }
    const ReinhardMapping m = resolveReinhard(*stats, params);
    const LuminanceWeights w = params.metering.weights;
    return detail::mapColour(dst, src, roi, nthreads, [&](const float* p, int, int) {
        const double Lw = luminance(p[0], p[1], p[2], w);
        // Colour scaled by Ld / Lw keeps the chromaticity (the paper maps luminance).
        const double ratio = Lw > 0.0 ? reinhardCurve(m.scale * Lw, m.white) / Lw : 0.0;
        return glm::vec3(float(double(p[0]) * ratio), float(double(p[1]) * ratio),
                         float(double(p[2]) * ratio));
    });
}

} // namespace dhdr
