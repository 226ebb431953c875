// Bloom in HDR: the glow that very bright pixels spread around them.
#pragma once

#include <dhdr/common/param_table.h>
#include <dhdr/tonemap/luminance.h>
#include <memory>
#include <string>

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

// BloomParams' ranges, and the options of dhdr-bloom and keywords of dhdr.bloom() that set them.
inline constexpr FloatParam<BloomParams> kBloomFloatTable[] = {
    {"--threshold",
     "threshold",
     &BloomParams::threshold,
     {0.0, 1.0, false, true},
     "T",
     "tone-mapped luminance L/(1+L) above which pixels bloom"},
    {"--key", "key", &BloomParams::key, {0.0, 100.0, true}, "A", "key α of that tone mapping"},
    {"--sigma", "sigma", &BloomParams::sigma, {0.0, 64.0}, "S", "Gaussian σ in 1/8-size pixels"},
    {"--strength",
     "strength",
     &BloomParams::strength,
     {0.0, 1000.0},
     "K",
     "factor of the bloom layer"},
};

// Bloom of a frame that arrives strip by strip, in two passes over it (dhdr-bloom streams
// frames this way, so that its memory is a strip and the 1/4-size copy): addRows() meters the
// rows and reduces them to the quarter-size copy; finish() makes the blurred 1/8-size layer;
// apply() adds it to any strip. The whole-image functions below are this, on one strip, so
// both give the same pixels.
class BloomBuilder {
public:
    // `frame`: the whole frame's pixels (rows [ybegin, yend), columns [xbegin, xend)).
    BloomBuilder(OIIO::ROI frame, const BloomParams& params = {}, int nthreads = 0);
    ~BloomBuilder();
    BloomBuilder(const BloomBuilder&) = delete;
    BloomBuilder& operator=(const BloomBuilder&) = delete;

    // First pass: the strip's rows, each after those above it, whole rows of the frame;
    // R, G, B are channels 0–2 and alpha (metering leaves alpha-0 pixels out) channel 3.
    bool addRows(const OIIO::ImageBuf& strip);
    // After the last row: the metering, the bright pass, the 1/8-size blurred layer.
    bool finish();
    // Second pass: dst = src + strength · layer on R, G, B over `roi` (default: all of
    // `src`); other channels copied. dst may be src.
    bool apply(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi = {}) const;
    // The layer's value (before strength) at frame pixel (x, y).
    void layerAt(int x, int y, float rgb[3]) const;
    const std::string& error() const { return m_error; }

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    std::string m_error;
};

// The bloom layer alone: a 3-channel float image of `src`'s size (before `strength`).
bool bloomLayer(OIIO::ImageBuf& layer, const OIIO::ImageBuf& src, const BloomParams& params = {},
                int nthreads = 0);

// dst = src + strength · bloomLayer(src) on the colour channels; every other channel is
// copied. `roi` limits where the layer is added.
bool bloom(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const BloomParams& params = {},
           OIIO::ROI roi = {}, int nthreads = 0);

} // namespace dhdr
