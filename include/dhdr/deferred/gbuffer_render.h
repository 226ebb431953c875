// The primary-ray pass that fills a G-buffer from a scene.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dhdr {

struct Camera;
class RayCaster;
struct Scene;

struct GBufferParams {
    int width = 1920;
    int height = 1080;
    // Called now and then from the rendering threads with the fraction of rows done of the
    // region being rendered, in [0, 1].
    std::function<void(float)> progress;
};

// Casts one primary ray through each pixel centre and writes the channels of the G-buffer
// contract (gbuffer::channelNames()) as float pixels. Background pixels have A = 0, Z = +∞,
// zero elsewhere and ids 0; ids index the name tables in the spec, whose entry 0 is the
// background. The acceleration structure is built once, so a caller can render a large frame
// strip by strip and write each strip as it is done.
class GBufferRenderer {
public:
    // `scene` and `camera` must outlive the renderer.
    GBufferRenderer(const Scene& scene, const Camera& camera, const GBufferParams& params);
    ~GBufferRenderer();

    bool ok() const;
    const std::string& error() const;

    // The whole frame's spec: size, channel names, camera matrices, name tables.
    const OIIO::ImageSpec& spec() const { return m_spec; }

    // Renders the pixels of `roi` (default: the whole frame) into `dst`, which becomes a float
    // image with spec() over exactly that region (its data window) when it is not already.
    bool render(OIIO::ImageBuf& dst, OIIO::ROI roi = {}, int nthreads = 0) const;

private:
    const Scene& m_scene;
    const Camera& m_camera;
    GBufferParams m_params;
    OIIO::ImageSpec m_spec;
    std::unique_ptr<RayCaster> m_caster;
};

// The whole frame in one call.
bool renderGBuffer(OIIO::ImageBuf& dst, const Scene& scene, const Camera& camera,
                   const GBufferParams& params, int nthreads = 0);

// The per-channel file types of the contract (half, float or uint), for writing.
std::vector<OIIO::TypeDesc> gbufferChannelFormats();

} // namespace dhdr
