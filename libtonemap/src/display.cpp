#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cstdint>
#include <dhdr/tonemap/display.h>

namespace dhdr {

bool encodeSRGB(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi, int nthreads) {
    if (!detail::prepareFloatDst(dst, src, roi, 3)) return false;
    const detail::FloatPixels in(src);
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float* p = in.at(x, y);
                float* q = detail::floatPixel(dst, x, y);
                for (int c = 0; c < 3; ++c)
                    q[c] = srgbEncode(p[c]);
                for (int c = 3; c < r.chend; ++c)
                    q[c] = p[c];
            }
    });
    return true;
}

namespace {

// A uniform number in [0, 1) from a 32-bit integer hash (Wellons' "lowbias32").
float hashUniform(std::uint32_t v) {
    v ^= v >> 16;
    v *= 0x7feb352dU;
    v ^= v >> 15;
    v *= 0x846ca68bU;
    v ^= v >> 16;
    return float(v >> 8) * (1.0f / 16777216.0f);
}

} // namespace

bool addDither(OIIO::ImageBuf& img, int bits, unsigned seed, OIIO::ROI roi, int nthreads) {
    if (img.spec().format != OIIO::TypeDesc::FLOAT || !img.localpixels() || img.nchannels() < 3) {
        img.errorfmt("dithering needs float pixels in memory with three colour channels");
        return false;
    }
    if (!roi.defined()) roi = img.roi();
    const float step = 1.0f / float((1u << bits) - 1u);
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                float* p = detail::floatPixel(img, x, y);
                for (int c = 0; c < 3; ++c) {
                    const std::uint32_t key = (std::uint32_t(y) * 0x9E3779B1u) ^
                                              (std::uint32_t(x) * 0x85EBCA77u) ^
                                              (std::uint32_t(c) * 0xC2B2AE3Du) ^ seed;
                    // The sum of two uniforms minus one: triangular on (−1, 1), mean 0.
                    const float noise = hashUniform(key) + hashUniform(key ^ 0x68E31DA4u) - 1.0f;
                    p[c] = std::clamp(p[c] + noise * step, 0.0f, 1.0f);
                }
            }
    });
    return true;
}

} // namespace dhdr
