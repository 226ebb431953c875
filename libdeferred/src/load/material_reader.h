// A scene's materials: Assimp's materials (glTF's, or OBJ/MTL's), with what Assimp 5.2 leaves
// out of glTF ones read from the file's JSON, into Scene::materials.
#pragma once

#include "load/texture_loader.h"

#include <dhdr/deferred/scene/scene.h>
#include <nlohmann/json.hpp>

struct aiScene;

namespace dhdr::detail {

// Appends the materials of `ai` to `scene`, their textures through `textures`; a default one
// when the file has none. `doc`: the glTF file's JSON (gltfJson), used when `gltf`.
void readMaterials(const aiScene& ai, const nlohmann::json& doc, bool gltf, TextureTable& textures,
                   Scene& scene);

} // namespace dhdr::detail
