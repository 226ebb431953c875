// What Debian's Assimp 5.2 drops from glTF files, read from the file's own JSON.
#pragma once

#include <map>
#include <string>

namespace dhdr::detail {

// KHR_materials_emissive_strength per material name, from a .gltf or .glb file. Empty for
// other files, or when no material uses the extension.
std::map<std::string, float> gltfEmissiveStrengths(const std::string& path);

} // namespace dhdr::detail
