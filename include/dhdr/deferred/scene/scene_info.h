// What a scene holds, as text for a person: `dhdr-gbuffer --info` and the Python module's
// Scene.info().
#pragma once

#include <dhdr/deferred/scene/scene.h>
#include <string>
#include <vector>

namespace dhdr {

// Bounds, objects and triangles, cameras (name, projection, field of view or height),
// lights, the materials in use with their factors, textures and extensions, and what the
// loader left out.
std::string describeScene(const Scene& scene, const std::string& path);

// The indices of the materials that a mesh or the ground plane uses, in order: Assimp adds a
// default material to every glTF file and some OBJ files, which no mesh may use.
std::vector<int> materialsInUse(const Scene& scene);

// "opaque", "mask" or "blend", glTF's alphaMode in lower case.
const char* alphaModeName(AlphaMode mode);

// One texture a material uses: its slot as --info writes it ("base colour") and as the Python
// module's Scene.materials keys it ("base_color"), and the reference.
struct MaterialTexture {
    const char* slot;
    const char* key;
    const TextureRef* ref;
};
std::vector<MaterialTexture> materialTextures(const Material& m);

} // namespace dhdr
