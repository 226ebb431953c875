// The photographic tone-reproduction operator of Reinhard et al. 2002 (global version).
#pragma once

#include <cmath>
#include <dhdr/tonemap/luminance.h>
#include <limits>

namespace dhdr {

// Ld = L (1 + L / Lwhite²) / (1 + L), Reinhard et al. 2002 eq. 4. With Lwhite = ∞ this is
// L / (1 + L); L = Lwhite maps to exactly 1.
inline double reinhardCurve(double L, double Lwhite) {
    const double burn = std::isinf(Lwhite) ? 0.0 : L / (Lwhite * Lwhite);
    return L * (1.0 + burn) / (1.0 + L);
}

struct ReinhardParams {
    // Key α: the scene's log-average is mapped to this value (eq. 2).
    double key = 0.18;
    // Exposure in stops, applied on top of the key: L = 2^exposure · α · Lw / L̄w.
    double exposure = 0.0;
    // Lwhite in scaled luminance. Zero or negative: the largest L in the image (the paper's
    // default). +∞: plain L / (1 + L).
    double white = 0.0;
    LuminanceStatsParams metering;
    // Metering to use instead of measuring `src` (a sequence's adapted luminance, or
    // statistics the caller already has). Not owned.
    const LuminanceStats* stats = nullptr;
};

// The scale L = scale · Lw and the white point that `params` resolve to for `stats`.
struct ReinhardMapping {
    double scale = 1.0;
    double white = std::numeric_limits<double>::infinity();
};
ReinhardMapping resolveReinhard(const LuminanceStats& stats, const ReinhardParams& params);

// Tone-maps the RGB channels of `src` into `dst`: each colour is scaled by Ld / Lw, so hue and
// saturation are kept. Further channels (alpha) are copied. Output is display-linear, not yet
// encoded for a display.
bool reinhard(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const ReinhardParams& params = {},
              OIIO::ROI roi = {}, int nthreads = 0);

} // namespace dhdr
