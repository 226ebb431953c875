// The tone-map operators of dhdr-tonemap behind one call.
#pragma once

#include <dhdr/common/param_table.h>
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

// An operator's name among kToneMapChoiceTable's ("reinhard", "pbr-neutral", ...).
bool parseToneOperator(const std::string& name, ToneOperator& op);
std::string toneOperatorName(ToneOperator op);

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

// Reinhard's white point as the tools and the Python module take it (`--white`, `white=`):
// "auto" (0: the image's largest luminance), "inf" (+∞: no white point) or a positive finite
// number, into `white`; false with "--white must be …" or "white must be …, got 'text'".
bool parseWhite(const std::string& text, double& white, Spelling spelling, std::string& error);

// ToneMapParams' operator, and the option of dhdr-tonemap and keyword of dhdr.tone_map() that
// set it; the names in ToneOperator's order.
inline constexpr ChoiceParam<ToneMapParams> kToneMapChoiceTable[] = {
    {"--op", "op", "reinhard|reinhard-local|drago|hable|pbr-neutral|agx|exposure|aces|none",
     [](const ToneMapParams& p) { return int(p.op); },
     [](ToneMapParams& p, int i) { p.op = ToneOperator(i); },
     "the tone-map operator; aces is the ACES 1.0 SDR output transform, as the view; none is "
     "scene-linear x 2^exposure, unclipped, to the display/view (a config's own view such as "
     "Filmic or AgX tone-maps)"},
};

// ToneMapParams' ranges, and the options of dhdr-tonemap and keywords of dhdr.tone_map() that
// set them.
inline constexpr FloatParam<ToneMapParams, double> kToneMapFloatTable[] = {
    {"--key",
     "key",
     &ToneMapParams::key,
     {0.0, 100.0, true},
     "A",
     "key α: the metered luminance maps to this"},
    {"--exposure",
     "exposure",
     &ToneMapParams::exposure,
     {-64.0, 64.0},
     "STOPS",
     "extra exposure in stops"},
    {"--phi",
     "phi",
     &ToneMapParams::phi,
     {0.0, 100.0, true},
     "PHI",
     "reinhard-local's sharpening φ"},
    {"--epsilon",
     "epsilon",
     &ToneMapParams::epsilon,
     {0.0, 1.0, true},
     "EPS",
     "reinhard-local's activity threshold ε"},
    {"--drago-bias",
     "drago_bias",
     &ToneMapParams::dragoBias,
     {0.0, 1.0, true},
     "B",
     "drago's bias: lower brightens the dark tones"},
};

// Tone-maps the RGB of `src` into display-linear RGB in `dst` (float; alpha and further
// channels copied). Luminance operators (reinhard, reinhard-local, drago) scale each colour by
// Ld / Lw; the others act per channel.
bool toneMap(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const ToneMapParams& params = {},
             OIIO::ROI roi = {}, int nthreads = 0);

} // namespace dhdr
