#include "native_pixels.h"

#include <Imath/half.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace dhdr {

NativeReader::NativeReader(const OIIO::ImageSpec& spec, int chbegin, int chend) {
    for (int c = chbegin; c < chend; ++c) {
        types.push_back(spec.channelformat(c));
        offsets.push_back(bytes);
        bytes += types.back().size();
        uniform = uniform && types.back() == types.front();
    }
}

bool NativeReader::toFloat(const std::byte* native, float* pixels, int width, int height) const {
    const int nch = int(types.size());
    const bool anyUint = std::any_of(types.begin(), types.end(), [](OIIO::TypeDesc t) {
        return t.basetype == OIIO::TypeDesc::UINT32;
    });
    if (uniform && !anyUint)
        return OIIO::convert_pixel_values(types[0], native, OIIO::TypeDesc::FLOAT, pixels,
                                          width * height * nch);
    const auto dstPixel = OIIO::stride_t(nch * sizeof(float));
    for (int c = 0; c < nch; ++c) {
        if (types[size_t(c)].basetype == OIIO::TypeDesc::UINT32) {
            // An id, not a fraction of full scale.
            const size_t n = size_t(width) * size_t(height);
            for (size_t i = 0; i < n; ++i) {
                std::uint32_t v;
                std::memcpy(&v, native + i * bytes + offsets[size_t(c)], sizeof v);
                pixels[i * size_t(nch) + size_t(c)] = float(v);
            }
            continue;
        }
        if (!OIIO::convert_image(1, width, height, 1, native + offsets[size_t(c)], types[size_t(c)],
                                 OIIO::stride_t(bytes), OIIO::stride_t(bytes) * width,
                                 OIIO::AutoStride, pixels + c, OIIO::TypeDesc::FLOAT, dstPixel,
                                 dstPixel * width, OIIO::AutoStride))
            return false;
    }
    return true;
}

NativeWriter::NativeWriter(const OIIO::ImageSpec& spec, int infinityAllowed)
    : m_infinity(infinityAllowed) {
    for (int c = 0; c < spec.nchannels; ++c) {
        m_types.push_back(spec.channelformat(c));
        m_offsets.push_back(m_bytes);
        m_bytes += m_types.back().size();
    }
}

void NativeWriter::convert(const float* pixels, size_t count, std::byte* native, long long& clamped,
                           long long& nonFinite) const {
    constexpr float kHalfMax = 65504.0f;
    constexpr float kFloatMax = std::numeric_limits<float>::max();
    const size_t nch = m_types.size();
    for (size_t i = 0; i < count; ++i) {
        for (size_t c = 0; c < nch; ++c) {
            float v = pixels[i * nch + c];
            std::byte* out = native + i * m_bytes + m_offsets[c];
            const bool keepInfinity = int(c) == m_infinity && v == INFINITY;
            if (std::isnan(v)) {
                v = 0.0f;
                ++nonFinite;
            } else if (std::isinf(v) && !keepInfinity) {
                v = v > 0.0f ? kFloatMax : -kFloatMax;
                ++nonFinite;
            }
            switch (m_types[c].basetype) {
            case OIIO::TypeDesc::HALF: {
                if (!keepInfinity && std::abs(v) > kHalfMax) {
                    v = std::copysign(kHalfMax, v);
                    ++clamped;
                }
                const Imath::half h(v);
                std::memcpy(out, &h, sizeof h);
                break;
            }
            case OIIO::TypeDesc::UINT32: {
                const double d = std::clamp(std::round(double(v)), 0.0, 4294967295.0);
                const auto u = std::uint32_t(d);
                std::memcpy(out, &u, sizeof u);
                break;
            }
            default: {
                // Float, and anything else a caller would have converted already.
                const float f = v;
                std::memcpy(out, &f, sizeof f);
                break;
            }
            }
        }
    }
}

} // namespace dhdr
