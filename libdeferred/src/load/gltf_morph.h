// Morph targets, read from the glTF file itself: Assimp 5.2 stores them as absolute positions,
// clamps negative weights and merges vertices, so a morphing primitive's vertices, triangles,
// UVs and targets come from the file's accessors (docs/scenes.md).
#pragma once

#include "load/gltf_buffers.h"

#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <nlohmann/json.hpp>
#include <string>

namespace dhdr::detail {

// Whether primitive `primitive` of node `node`'s mesh has morph targets, or is skinned (the node
// names a skin and the primitive has JOINTS_0 and WEIGHTS_0).
bool gltfIsDeformed(const nlohmann::json& doc, int node, unsigned primitive);

// Reads that primitive into `rest` (the node-space vertices, normals, targets, default
// weights, joints and their weights) and `mesh` (its triangles and UVs; positions and normals
// sized, for ScenePoser to fill). Triangle lists only. False with `error` naming the accessor and
// what is wrong.
bool gltfMorphPrimitive(const nlohmann::json& doc, GltfBuffers& buffers, int node,
                        unsigned primitive, MeshRest& rest, Mesh& mesh, std::string& error);

} // namespace dhdr::detail
