#include <algorithm>
#include <dhdr/deferred/gbuffer/gbuffer_depth.h>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr {

bool tracesLayers(GBufferDepth depth, const Scene& scene) {
    if (depth != GBufferDepth::Auto) return depth == GBufferDepth::Deep;
    return std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) {
        return m.alphaMode == AlphaMode::Blend || m.transmission > 0.0f;
    });
}

} // namespace dhdr
