// The tone-map operators of dhdr-tonemap behind one call.
#pragma once

#include <dhdr/tonemap/curves.h>
#include <dhdr/tonemap/metering.h>
#include <string>

namespace dhdr {

enum class ToneOperator {
    Reinhard,      // Reinhard et al. 2002, global (reinhard.h)
    ReinhardLocal, // Reinhard et al. 2002, dodging-and-burning (local_reinhard.h)
    Drago,         // Drago et al. 2003, adaptive logarithmic
    Hable,         // Hable's filmic curve, per channel
    PbrNeutral,    // Khronos PBR Neutral
    Agx,           // AgX, polynomial form
    Exposure,      // linear: × 2^exposure, clipped
    Aces,          // metered exposure only; the ACES output transform is the display's view
    None,          // × 2^exposure only, unclipped: the display's view does the tone mapping
};

// "reinhard", "reinhard-local", "drago", "hable", "pbr-neutral", "agx", "exposure", "aces",
// "none".
bool parseToneOperator(const std::string& name, ToneOperator& op);
const char* toneOperatorName(ToneOperator op);

struct ToneMapParams {
    ToneOperator op = ToneOperator::Reinhard;
    // Every operator but `exposure` and `none` first scales the image by 2^exposure · key / L̄w,
    // so the metered luminance L̄w lands on the key.
    double key = 0.18;
    double exposure = 0.0; // stops
    // Reinhard's white point (reinhard.h): ≤ 0 the largest, +∞ none.
    double white = 0.0;
    MeteringParams metering;
    // Metering to use instead of measuring `src` (e.g. a sequence's adapted luminance).
    const LuminanceStats* stats = nullptr;
    double phi = 8.0, epsilon = 0.05; // reinhard-local
    double dragoBias = 0.85;          // drago
    HableParams hable;
};

// Tone-maps the RGB of `src` into display-linear RGB in `dst` (float; alpha and further
// channels copied). Luminance operators (reinhard, reinhard-local, drago) scale each colour by
// Ld / Lw; the others act per channel.
bool toneMap(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const ToneMapParams& params = {},
             OIIO::ROI roi = {}, int nthreads = 0);

} // namespace dhdr
