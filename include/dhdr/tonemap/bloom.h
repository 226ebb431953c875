// Bloom in HDR: the glow that very bright pixels spread around them.
#pragma once

#include <dhdr/tonemap/luminance.h>

namespace dhdr {

// The seeds' pipeline: quarter-size copy, bright pass, downsample to 1/8, separable Gaussian,
// bilinear upsample, added to the image.
struct BloomParams {
    // Bright pass: a pixel blooms when its tone-mapped luminance L / (1 + L), with
    // L = key · Lw / L̄w, exceeds this.
    float threshold = 0.8f;
    // The key α used for that tone mapping.
    float key = 0.18f;
    LuminanceStatsParams metering;
    // Standard deviation of the Gaussian, in pixels of the 1/8-size image.
    float sigma = 2.0f;
    // Factor of the bloom layer when it is added to the image.
    float strength = 1.3f;
};

// The bloom layer alone: a 3-channel float image of `src`'s size (before `strength`).
bool bloomLayer(OIIO::ImageBuf& layer, const OIIO::ImageBuf& src, const BloomParams& params = {},
                int nthreads = 0);

// dst = src + strength · bloomLayer(src) on the colour channels; every other channel is
// copied. `roi` limits where the layer is added.
bool bloom(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const BloomParams& params = {},
           OIIO::ROI roi = {}, int nthreads = 0);

} // namespace dhdr
