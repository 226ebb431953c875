// The primary-ray pass that fills a G-buffer from a scene.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <functional>
#include <vector>

namespace dhdr {

struct Camera;
struct Scene;

struct GBufferParams {
    int width = 1920;
    int height = 1080;
    // Called now and then from the rendering threads with the fraction done, in [0, 1].
    std::function<void(float)> progress;
};

// Casts one primary ray through each pixel centre and writes the channels of the G-buffer
// contract (gbuffer::channelNames()) into `dst` as float pixels, with the camera matrices and
// the object and material name tables in its spec. Background pixels have A = 0, Z = +∞,
// zero elsewhere and ids 0; ids index the name tables, whose entry 0 is the background.
bool renderGBuffer(OIIO::ImageBuf& dst, const Scene& scene, const Camera& camera,
                   const GBufferParams& params, int nthreads = 0);

// The per-channel file types of the contract (half, float or uint), for writing `dst`.
std::vector<OIIO::TypeDesc> gbufferChannelFormats();

} // namespace dhdr
