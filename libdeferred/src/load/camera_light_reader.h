// What a node holds besides meshes: Assimp's cameras and lights, each linked to its node by
// name and placed by the node's world transform, with the fields Assimp 5.2 loses of a glTF
// camera or KHR_lights_punctual light read from the file's JSON; into Scene::cameras and
// Scene::lights, kept in the rig to move with their nodes.
#pragma once

#include "load/rig_loader.h"

#include <assimp/scene.h>
#include <dhdr/deferred/scene/scene.h>
#include <functional>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <string>

namespace dhdr::detail {

// The world transform of the node with a name (the first one, depth first).
using NodeWorld = std::function<glm::dmat4(const aiString& name)>;

// Appends the cameras of `ai` to `scene`; one that cannot be rendered from is kept with its
// problem and a warning. `doc`: the glTF file's JSON (gltfJson), used when `gltf`.
void readCameras(const aiScene& ai, const nlohmann::json& doc, bool gltf, const NodeWorld& world,
                 Scene& scene, RigLoader& rig);

// Appends the lights of `ai` to `scene` (ambient ones are left out). False with `error`
// (naming `path`) when the file's KHR_lights_punctual lights cannot be read.
bool readLights(const aiScene& ai, const std::string& path, const nlohmann::json& doc, bool gltf,
                const NodeWorld& world, Scene& scene, RigLoader& rig, std::string& error);

} // namespace dhdr::detail
