// Whether a G-buffer is written flat or deep (docs/gbuffer.md): dhdr-gbuffer's --deep and
// --flat, render_gbuffer's deep=True/False/'auto'. By default a deep G-buffer is written only
// when some pixel holds a partly transparent surface or one that light passes (transmission).
#pragma once

namespace dhdr {

struct Scene;

enum class GBufferDepth {
    Auto, // deep when a partly transparent surface is in view (the default)
    Deep, // always deep (--deep)
    Flat, // never deep: each pixel's first surface, transparent or not (--flat)
};

// Whether the layers of a G-buffer of `scene` are traced: always for Deep, never for Flat,
// and for Auto when some material blends or transmits (only such a material makes a surface
// that shows what lies behind it), to find whether one is in view.
bool tracesLayers(GBufferDepth depth, const Scene& scene);

// Whether the G-buffer is written deep, once tracing its layers found `transparent` partly
// transparent samples.
inline bool writtenDeep(GBufferDepth depth, long long transparent) {
    return depth == GBufferDepth::Deep || transparent > 0;
}

} // namespace dhdr
