// What loadScene keeps of a glTF file with animations to re-pose it later (SceneRig): its node
// tree paired with Assimp's, its animations and skins, and each mesh's, camera's and light's
// node and node-space data. Assimp types stay in the library.
#pragma once

#include "load/gltf_buffers.h"

#include <assimp/scene.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

namespace dhdr::detail {

class RigLoader {
public:
    // Starts a rig when `doc` (the JSON of the glTF file at `path`, loaded by Assimp as `ai`)
    // has animations; else active() is false and the other calls do nothing.
    RigLoader(const aiScene& ai, const std::string& path, const nlohmann::json& doc);

    bool active() const { return bool(m_rig); }
    // A skin the file gets wrong (the load fails with it), empty when none.
    const std::string& error() const { return m_error; }

    // A mesh's vertices as the file gives them, in its node's space (ScenePoser applies the
    // node's world transform to them as the loader does).
    MeshRest restOf(const aiMesh& am, const aiNode& node) const;
    // Whether the mesh `rest` (the node's `primitive`-th) is morphed or skinned: then its data
    // come from the file (readDeformed), not from Assimp.
    bool deformed(const MeshRest& rest, unsigned primitive) const;
    // Reads such a primitive into `mesh` and `rest`, posed with its default weights and its
    // joints at rest. False with `error` naming the file, the node and the primitive.
    bool readDeformed(Mesh& mesh, MeshRest& rest, const glm::dmat4& world, unsigned primitive,
                      std::string& error);

    // Records, in the order the scene receives them, a mesh, a camera and a light.
    void keepMesh(MeshRest rest);
    void keepCamera(const aiString& nodeName);
    void keepLight(const aiLight& light);

    std::shared_ptr<const SceneRig> finish() { return std::move(m_rig); }

private:
    bool matchNodes();
    int nodeIndexNamed(const aiString& name) const;

    const aiScene& m_ai;
    const std::string& m_path;
    const nlohmann::json& m_doc;
    std::shared_ptr<SceneRig> m_rig;
    std::unique_ptr<GltfBuffers> m_buffers;   // the file's buffers, read once
    std::map<const aiNode*, int> m_nodeIndex; // Assimp's nodes → the file's
    std::string m_error;
};

} // namespace dhdr::detail
