// Edge-detect anti-aliasing from geometric discontinuities (normal and depth).
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/common/param_table.h>

namespace dhdr {

// Blur factor e = wN · Σ_k |N_k − N|² + wZ · Σ_k ((Z_k − Z) / Z)² over the 8 neighbours k,
// clamped to [0, 1]. The seed sums squared differences of the normal; the depth term is
// relative so that it means the same at any distance.
struct EdgeAAParams {
    float normalWeight = 1.0f;
    float depthWeight = 1.0f;
    // Offset, in pixels, of the resampling taps at e = 1. Taps sit at e · maxOffset along the
    // 8 neighbour directions.
    float maxOffset = 0.5f;
};

// EdgeAAParams' ranges, and the options of dhdr-aa and keywords of dhdr.edge_aa() that set them.
inline constexpr FloatParam<EdgeAAParams> kEdgeAAFloatTable[] = {
    {"--normal-weight",
     "normal_weight",
     &EdgeAAParams::normalWeight,
     {0.0, 1e6},
     "W",
     "weight of Σ|ΔN|²"},
    {"--depth-weight",
     "depth_weight",
     &EdgeAAParams::depthWeight,
     {0.0, 1e6},
     "W",
     "weight of Σ(ΔZ/Z)²"},
    {"--max-offset",
     "max_offset",
     &EdgeAAParams::maxOffset,
     {0.0, 4.0},
     "PX",
     "tap offset at full blur, pixels"},
};

// The per-pixel blur factor as a 1-channel float image. `normal` (3 channels) and `depth`
// (1 channel) are optional, but not both absent; they must cover `roi`.
bool edgeBlurFactor(OIIO::ImageBuf& dst, const OIIO::ImageBuf* normal, const OIIO::ImageBuf* depth,
                    const EdgeAAParams& params = {}, OIIO::ROI roi = {}, int nthreads = 0);

// Resamples `src` where the blur factor is above zero: each pixel becomes the mean of 8
// bilinear taps around it at offset e · maxOffset. Where e = 0 the pixel is copied bit for
// bit. Every channel of `src` is filtered.
bool edgeAA(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const OIIO::ImageBuf* normal,
            const OIIO::ImageBuf* depth, const EdgeAAParams& params = {}, OIIO::ROI roi = {},
            int nthreads = 0);

} // namespace dhdr
