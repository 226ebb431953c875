#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <dhdr/tonemap/display.h>

namespace dhdr {

bool encodeSRGB(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi, int nthreads) {
    return detail::mapColour(dst, src, roi, nthreads, [](const float* p, int, int) {
        return glm::vec3(srgbEncode(p[0]), srgbEncode(p[1]), srgbEncode(p[2]));
    });
}

namespace {

// The 8 × 8 Bayer matrix: every threshold 0..63 once, neighbours far apart.
constexpr int kBayer[8][8] = {{0, 32, 8, 40, 2, 34, 10, 42},  {48, 16, 56, 24, 50, 18, 58, 26},
                              {12, 44, 4, 36, 14, 46, 6, 38}, {60, 28, 52, 20, 62, 30, 54, 22},
                              {3, 35, 11, 43, 1, 33, 9, 41},  {51, 19, 59, 27, 49, 17, 57, 25},
                              {15, 47, 7, 39, 13, 45, 5, 37}, {63, 31, 55, 23, 61, 29, 53, 21}};

} // namespace

bool addDither(OIIO::ImageBuf& img, int bits, OIIO::ROI roi, int nthreads) {
    if (img.spec().format != OIIO::TypeDesc::FLOAT || !img.localpixels() || img.nchannels() < 3) {
        img.errorfmt("dithering needs float pixels in memory with three colour channels");
        return false;
    }
    if (!roi.defined()) roi = img.roi();
    const float step = 1.0f / float((1u << bits) - 1u);
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                // An offset in (−½, ½) step whose 64 values average to 0 over every 8 × 8 tile.
                const float offset = (float(kBayer[y & 7][x & 7]) + 0.5f) / 64.0f - 0.5f;
                float* p = detail::floatPixel(img, x, y);
                for (int c = 0; c < 3; ++c)
                    p[c] = std::clamp(p[c] + offset * step, 0.0f, 1.0f);
            }
    });
    return true;
}

} // namespace dhdr
