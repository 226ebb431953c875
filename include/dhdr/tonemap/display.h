// Encoding display-linear values for an sRGB display.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <cmath>

namespace dhdr {

// The sRGB opto-electronic transfer function, IEC 61966-2-1, on [0, 1].
inline float srgbEncode(float v) {
    if (!(v > 0.0f)) return 0.0f;
    if (v >= 1.0f) return 1.0f;
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

// Applies srgbEncode to the colour channels (the first three) of `src`, clamping to [0, 1];
// alpha and further channels are copied unchanged.
bool encodeSRGB(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi = {},
                int nthreads = 0);

} // namespace dhdr
