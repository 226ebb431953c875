#include "native_write.h"

#include <Imath/half.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace dhdr::app {

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

} // namespace dhdr::app
