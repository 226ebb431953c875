#include <dhdr/tonemap/display.h>

#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>

namespace dhdr {

bool encodeSRGB(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi, int nthreads) {
    if (!detail::prepareFloatDst(dst, src, roi, 3)) return false;
    const detail::FloatPixels in(src);
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float* p = in.at(x, y);
                float* q = detail::floatPixel(dst, x, y);
                for (int c = 0; c < 3; ++c) q[c] = srgbEncode(p[c]);
                for (int c = 3; c < r.chend; ++c) q[c] = p[c];
            }
    });
    return true;
}

} // namespace dhdr
