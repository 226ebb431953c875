// Reinhard et al. 2002's local operator: automatic dodging-and-burning (section 3.2).
#pragma once

#include <OpenImageIO/imagebuf.h>

namespace dhdr {

struct LocalReinhardParams {
    double key = 0.18;     // α
    double phi = 8.0;      // φ, sharpening
    double epsilon = 0.05; // ε, the activity threshold
    int scales = 8;        // s = 1.6^i, i = 0 … scales − 1
};

// Maps a 1-channel image of scaled luminance L (= α Lw / L̄w) to display luminance
// Ld = L / (1 + V1(x, y, s_m)) (eq. 9), where V1 is L convolved with the Gaussian of scale s
// (α₁ = 1 / (2√2), eq. 5–6) and s_m the largest scale whose activity
// V = (V1(s) − V1(1.6 s)) / (2^φ α / s² + V1(s)) stays below ε (eq. 7–8).
bool localReinhard(OIIO::ImageBuf& dst, const OIIO::ImageBuf& scaledLuminance,
                   const LocalReinhardParams& params = {}, int nthreads = 0);

} // namespace dhdr
