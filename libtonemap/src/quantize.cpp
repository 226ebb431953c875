#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <dhdr/tonemap/quantize.h>
#include <limits>

namespace dhdr {

namespace {

// The 8 × 8 Bayer matrix: every threshold 0..63 once, neighbours far apart.
constexpr int kBayer[8][8] = {{0, 32, 8, 40, 2, 34, 10, 42},  {48, 16, 56, 24, 50, 18, 58, 26},
                              {12, 44, 4, 36, 14, 46, 6, 38}, {60, 28, 52, 20, 62, 30, 54, 22},
                              {3, 35, 11, 43, 1, 33, 9, 41},  {51, 19, 59, 27, 49, 17, 57, 25},
                              {15, 47, 7, 39, 13, 45, 5, 37}, {63, 31, 55, 23, 61, 29, 53, 21}};

template <typename T>
void quantizeRows(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, bool dither, OIIO::ROI r) {
    constexpr float kMax = float(std::numeric_limits<T>::max());
    const int nch = dst.nchannels();
    const int ditherChannels = dither ? std::min(nch, 3) : 0;
    for (int y = r.ybegin; y < r.yend; ++y) {
        const auto* in = static_cast<const float*>(src.pixeladdr(r.xbegin, y));
        auto* out = static_cast<T*>(dst.pixeladdr(r.xbegin, y));
        const int srcStride = src.nchannels();
        for (int x = r.xbegin; x < r.xend; ++x, in += srcStride, out += nch) {
            // Rounding is floor(v + ½); the dither offset moves the ½ in (0, 1).
            const float threshold = (float(kBayer[y & 7][x & 7]) + 0.5f) / 64.0f;
            for (int c = 0; c < nch; ++c) {
                const float v = std::clamp(in[c], 0.0f, 1.0f) * kMax;
                const float q = std::floor(v + (c < ditherChannels ? threshold : 0.5f));
                out[c] = T(std::min(q, kMax));
            }
        }
    }
}

} // namespace

bool quantize(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const QuantizeParams& params,
              OIIO::ROI roi, int nthreads) {
    const OIIO::TypeDesc type = dst.spec().format;
    if (!dst.initialized() || !dst.localpixels() ||
        (type != OIIO::TypeDesc::UINT8 && type != OIIO::TypeDesc::UINT16)) {
        dst.errorfmt("quantize needs a UINT8 or UINT16 destination in memory");
        return false;
    }
    if (!src.initialized() || src.spec().format != OIIO::TypeDesc::FLOAT || !src.localpixels() ||
        src.nchannels() < dst.nchannels()) {
        dst.errorfmt("quantize needs float source pixels in memory with at least {} channels",
                     dst.nchannels());
        return false;
    }
    if (!roi.defined()) roi = dst.roi();
    roi = OIIO::roi_intersection(OIIO::roi_intersection(roi, dst.roi()), src.roi());
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        if (type == OIIO::TypeDesc::UINT8)
            quantizeRows<uint8_t>(dst, src, params.dither, r);
        else
            quantizeRows<uint16_t>(dst, src, params.dither, r);
    });
    return true;
}

} // namespace dhdr
