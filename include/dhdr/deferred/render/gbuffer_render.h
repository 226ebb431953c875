// The primary-ray pass that fills a G-buffer from a scene.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <atomic>
#include <cstdint>
#include <dhdr/common/param_table.h>
#include <dhdr/deferred/render/pixel_filter.h>
#include <dhdr/deferred/scene/camera.h>
#include <dhdr/deferred/scene/frame_motion.h>
#include <dhdr/deferred/scene/texture.h>
#include <functional>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

namespace dhdr {

struct CryptoIds;
struct DeepGBuffer;
class RayCaster;
struct Scene;

struct GBufferParams {
    int width = 1920;
    int height = 1080;
    // Deep G-buffers (renderDeep): the most samples a pixel keeps, 1-64. The opaque surface
    // that ends a ray always has its place; Blend surfaces beyond the first maxLayers − 1 are
    // left out (they are the farthest).
    int maxLayers = 8;
    // How textures are filtered over each pixel's footprint (TextureFilter): anisotropic by
    // default, the nearest of the three to each pixel's average over its area (on a receding
    // checker, RMS 0.022 against 0.079 trilinear and 0.249 bilinear, bench/texture_filtering.py);
    // bilinear reads the full-size texture at the pixel's centre only.
    TextureFilter textureFilter = TextureFilter::Anisotropic;
    // Deep G-buffers: the primary rays of a pixel that takes several (docs/gbuffer.md, "Samples
    // and the pixel filter"), a square (1, 4, 9, … 64), stratified and drawn from the pixel
    // filter, each ray's surfaces a share 1 / samples of the pixel. 1: one ray through each
    // pixel's centre (a flat G-buffer's pixels).
    int samples = 1;
    // With samples > 1: every pixel takes them (true), or only the pixels whose centre ray sees
    // another surface than a neighbour's or a corner's (render/pixel_samples.h); the others
    // take one ray through the centre, the one-ray frame's pixel bit for bit.
    bool allPixels = false;
    PixelFilter pixelFilter = PixelFilter::BlackmanHarris; // Cycles' default
    float filterWidth = 1.5f; // pixels, the filter's whole support (Cycles' default)
    // Called now and then from the rendering threads with the fraction of rows done of the
    // region being rendered, in [0, 1].
    std::function<void(float)> progress;
    // Set from another thread to stop early (dhdr.render_gbuffer on Ctrl-C): rows not begun
    // are left out and render/renderDeep return false, their output to be thrown away.
    const std::atomic<bool>* cancel = nullptr;
    // With animation: the scene one frame before and one after, for the motion layer
    // (gbuffer::kMotion, docs/animation.md); null (the default) writes none.
    std::shared_ptr<const FrameMotion> motion;
};

// GBufferParams' ranges, and the options of dhdr-gbuffer and keywords of
// dhdr.render_gbuffer() that set them.
inline constexpr IntParam<GBufferParams> kGBufferParamTable[] = {
    {"--max-layers", &GBufferParams::maxLayers, 1, 64, "N",
     "deep G-buffers: at most N samples a pixel; the opaque surface keeps its place, Blend "
     "surfaces beyond the first N-1 are left out",
     "max_layers"},
    {"--pixel-samples", &GBufferParams::samples, 1, 64, "N",
     "primary rays a pixel takes where it needs more than one (a square: 1, 4, 9, 16, …), "
     "drawn from the pixel filter; 1 is one ray through each pixel's centre",
     "pixel_samples"},
};

inline constexpr FloatParam<GBufferParams> kGBufferFloatTable[] = {
    {"--filter-width",
     "filter_width",
     &GBufferParams::filterWidth,
     {0.5, 6.0},
     "PX",
     "the pixel filter's whole width in pixels: a ray lands up to half of it from the pixel's "
     "centre"},
};

// The error when `samples` is not a square (its strata are a grid), else empty.
std::string samplesError(int samples);

// GBufferParams' choices.
inline constexpr ChoiceParam<GBufferParams> kGBufferChoiceTable[] = {
    {"--texture-filter", "texture_filter", "bilinear|trilinear|anisotropic",
     [](const GBufferParams& p) { return int(p.textureFilter); },
     [](GBufferParams& p, int i) { p.textureFilter = TextureFilter(i); },
     "how textures are filtered over a pixel's footprint: one bilinear lookup of the full-size "
     "texture at the pixel's centre (distant textures shimmer); trilinear, the two mip levels "
     "of the footprint's longer side (blurs floors seen at grazing angles); or anisotropic, up "
     "to 8 trilinear lookups along a slanted footprint at the level of its shorter side"},
    {"--pixel-sampling", "pixel_sampling", "adaptive|all",
     [](const GBufferParams& p) { return int(p.allPixels); },
     [](GBufferParams& p, int i) { p.allPixels = i == 1; },
     "which pixels take --pixel-samples rays: those whose centre ray sees another surface than a "
     "neighbour's or a corner's (an edge, a crease, a step in depth, something thin), the others "
     "one ray through the centre; or all of them"},
    {"--pixel-filter", "pixel_filter", "box|gaussian|blackman-harris",
     [](const GBufferParams& p) { return int(p.pixelFilter); },
     [](GBufferParams& p, int i) { p.pixelFilter = PixelFilter(i); },
     "the filter rays are drawn from: box, a Gaussian of sigma width/6, or Blackman-Harris "
     "(Cycles' default); each ray is an equal share of its own pixel"},
};

// Casts primary rays through each pixel centre and writes the channels of the G-buffer
// contract (gbuffer::channelNames()) as float pixels. Background pixels have A = 0, Z = +∞,
// zero elsewhere and ids 0; ids index the name tables in the spec, whose entry 0 is the
// background. The acceleration structure is built once, so a caller can render a large frame
// strip by strip and write each strip as it is done.
class GBufferRenderer {
public:
    // `scene` and `camera` must outlive the renderer.
    GBufferRenderer(const Scene& scene, const Camera& camera, const GBufferParams& params);
    // The same with a ray caster the caller built over `scene` (and may refit between frames
    // of an animation, RayCaster::updateMeshes).
    GBufferRenderer(const Scene& scene, const Camera& camera, const GBufferParams& params,
                    std::shared_ptr<const RayCaster> caster);
    ~GBufferRenderer();

    bool ok() const;
    const std::string& error() const;

    // The whole frame's spec: size, channel names, camera matrices, name tables.
    const OIIO::ImageSpec& spec() const { return m_spec; }
    // The channels of renderDeep's samples: the deep contract's (with the WhenUsed ones the
    // scene uses), then the motion layer's when there is one.
    std::vector<std::string> deepChannelNames() const;

    // Renders the pixels of `roi` (default: the whole frame) into `dst`, which becomes a float
    // image with spec() over exactly that region (its data window) when it is not already.
    // The first surface of each pixel (Mask cut-outs skipped; a Blend surface is the first
    // like any other, with A = 1).
    bool render(OIIO::ImageBuf& dst, OIIO::ROI roi = {}, int nthreads = 0) const;

    // Every surface of each pixel of `roi` front to back, up to and including the first
    // opaque one (GBufferParams::maxLayers), A being each one's alpha: a deep G-buffer of
    // those rows; along each of a pixel's rays where it takes several (GBufferParams::samples,
    // sample.id and sample.weight). `deepSamples` counts the samples a flat G-buffer could not
    // hold: those with A < 1 and those of pixels of several rays.
    bool renderDeep(DeepGBuffer& dst, OIIO::ROI roi = {}, int nthreads = 0,
                    long long* deepSamples = nullptr) const;

private:
    // Whether each pixel of `rows` takes several rays (pixel_samples.h), row after row.
    std::vector<std::uint8_t> refinedPixels(OIIO::ROI rows, int nthreads) const;
    bool cancelled() const {
        return m_params.cancel && m_params.cancel->load(std::memory_order_relaxed);
    }

    const Scene& m_scene;
    const Camera& m_camera;
    GBufferParams m_params;
    unsigned m_uses; // what the scene's materials use (gbuffer::ChannelUse): channels written
    OIIO::ImageSpec m_spec;
    std::shared_ptr<const RayCaster> m_caster;
    std::shared_ptr<const CryptoIds> m_crypto; // the Cryptomatte ids of names
};

// The whole frame in one call.
bool renderGBuffer(OIIO::ImageBuf& dst, const Scene& scene, const Camera& camera,
                   const GBufferParams& params, int nthreads = 0);

} // namespace dhdr
