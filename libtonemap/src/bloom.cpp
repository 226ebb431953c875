#include "float_pixels.h"
#include "rgb_plane.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <dhdr/common/parallel.h>
#include <dhdr/tonemap/bloom.h>

namespace dhdr {

using detail::RgbPlane;

namespace {

RgbPlane quarterSize(const OIIO::ImageBuf& src, int nthreads) {
    const detail::FloatPixels in(src);
    const OIIO::ROI roi = src.roi();
    RgbPlane full(roi.width(), roi.height());
    OIIO::parallel_for(
        0, roi.height(),
        [&](int64_t y) {
            for (int x = 0; x < roi.width(); ++x) {
                const float* p = in.at(roi.xbegin + x, roi.ybegin + int(y));
                std::copy(p, p + 3, full.at(x, int(y)));
            }
        },
        perItem(nthreads));
    return detail::boxDownsample(full, std::max(1, full.width / 4), std::max(1, full.height / 4),
                                 nthreads);
}

// The seed's bright pass: the mean of the 8 neighbours (an 8-tap box, which keeps single
// fireflies from blooming alone), kept where its tone-mapped luminance exceeds the threshold.
// `logAverage` is the full image's, metered as the tone mapper meters it.
RgbPlane brightPass(const RgbPlane& src, double logAverage, const BloomParams& params,
                    int nthreads) {
    const double scale = logAverage > 0.0 ? params.key / logAverage : 0.0;

    RgbPlane out(src.width, src.height);
    OIIO::parallel_for(
        0, src.height,
        [&](int64_t yy) {
            const int y = int(yy);
            for (int x = 0; x < src.width; ++x) {
                float box[3] = {0.0f, 0.0f, 0.0f};
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        if (dx == 0 && dy == 0) continue;
                        const float* p = src.at(std::clamp(x + dx, 0, src.width - 1),
                                                std::clamp(y + dy, 0, src.height - 1));
                        for (int c = 0; c < 3; ++c)
                            box[c] += p[c] / 8.0f;
                    }
                const double L = scale * luminance(box[0], box[1], box[2], params.metering.weights);
                if (L / (1.0 + L) > double(params.threshold)) std::copy(box, box + 3, out.at(x, y));
            }
        },
        perItem(nthreads));
    return out;
}

} // namespace

bool bloomLayer(OIIO::ImageBuf& layer, const OIIO::ImageBuf& src, const BloomParams& params,
                int nthreads) {
    if (!src.initialized() || src.nchannels() < 3 || src.deep()) {
        layer.errorfmt("bloom needs a flat image with at least three channels");
        return false;
    }
    // Metered on the full image with its alpha, exactly as dhdr-tonemap meters it: pixels
    // with alpha 0 (no surface) are left out, so an empty background does not lower the key
    // and make everything bloom.
    LuminanceStats stats;
    computeLuminanceStats(stats, src, params.metering, {}, nthreads);
    const RgbPlane bright =
        brightPass(quarterSize(src, nthreads), stats.logAverage, params, nthreads);
    const RgbPlane eighth = detail::boxDownsample(bright, std::max(1, bright.width / 2),
                                                  std::max(1, bright.height / 2), nthreads);
    const RgbPlane blurred = detail::gaussianBlur(eighth, params.sigma, nthreads);

    const OIIO::ROI roi = src.roi();
    layer.reset(OIIO::ImageSpec(roi.width(), roi.height(), 3, OIIO::TypeDesc::FLOAT));
    layer.set_origin(roi.xbegin, roi.ybegin);
    const float sx = float(blurred.width) / float(roi.width());
    const float sy = float(blurred.height) / float(roi.height());
    OIIO::parallel_for(
        0, roi.height(),
        [&](int64_t y) {
            for (int x = 0; x < roi.width(); ++x)
                detail::bilinearSample(
                    blurred, (float(x) + 0.5f) * sx, (float(y) + 0.5f) * sy,
                    detail::floatPixel(layer, roi.xbegin + x, roi.ybegin + int(y)));
        },
        perItem(nthreads));
    return true;
}

bool bloom(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const BloomParams& params, OIIO::ROI roi,
           int nthreads) {
    OIIO::ImageBuf layer;
    if (!bloomLayer(layer, src, params, nthreads)) {
        dst.errorfmt("{}", layer.geterror());
        return false;
    }
    if (&dst != &src && !detail::prepareFloatDst(dst, src, roi, 3)) return false;
    if (!roi.defined()) roi = OIIO::roi_intersection(src.roi(), dst.roi());
    const detail::FloatPixels in(src);
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float* p = in.at(x, y);
                const float* b = static_cast<const float*>(layer.pixeladdr(x, y));
                float* q = detail::floatPixel(dst, x, y);
                for (int c = 0; c < 3; ++c)
                    q[c] = p[c] + params.strength * b[c];
            }
    });
    return true;
}

} // namespace dhdr
