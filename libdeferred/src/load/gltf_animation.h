// The node tree and the animations of a glTF file, read from its JSON: Assimp 5.2 makes STEP
// and CUBICSPLINE samplers linear and drops their tangents (docs/scenes.md).
#pragma once

#include "load/gltf_buffers.h"

#include <dhdr/deferred/scene/scene_rig.h>
#include <nlohmann/json.hpp>
#include <vector>

namespace dhdr::detail {

// The file's nodes with their rest transforms and parents, and an order with every parent
// before its children. False with `error` when the nodes do not form a forest.
bool gltfNodeTree(const nlohmann::json& doc, std::vector<SceneNode>& nodes, std::vector<int>& order,
                  std::string& error);

// The file's animations. One that cannot be played keeps its name and says why in
// Animation::problem (naming the sampler or channel), so that the others still play.
std::vector<Animation> gltfAnimations(const nlohmann::json& doc, GltfBuffers& buffers,
                                      const std::vector<SceneNode>& nodes);

// The file's skins. False with `error` naming the skin and what is wrong (a joint that is not a
// node, inverse bind matrices of the wrong type or count); a skin without inverseBindMatrices
// has identity ones.
bool gltfSkins(const nlohmann::json& doc, GltfBuffers& buffers, const std::vector<SceneNode>& nodes,
               std::vector<SceneSkin>& skins, std::string& error);

// The node indices of the default scene's roots ("scene", else scene 0), in the file's order.
std::vector<int> gltfSceneRoots(const nlohmann::json& doc);

// The children of node `n`, in the file's order (those that exist).
std::vector<int> gltfChildren(const nlohmann::json& doc, int n);

} // namespace dhdr::detail
