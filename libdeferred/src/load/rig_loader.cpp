#include "load/rig_loader.h"

#include "load/gltf_animation.h"
#include "load/gltf_json.h"
#include "load/gltf_morph.h"

namespace dhdr::detail {

// Assimp 5.2 builds its tree from the default scene's roots (under a "ROOT" node when there
// are several) in the file's order: the two trees are walked side by side.
RigLoader::RigLoader(const aiScene& ai, const std::string& path, const nlohmann::json& doc)
    : m_ai(ai), m_path(path), m_doc(doc) {
    if (!doc.is_object() || !doc.contains("animations") || !doc["animations"].is_array() ||
        doc["animations"].empty())
        return;
    m_rig = std::make_shared<SceneRig>();
    std::string why;
    if (gltfNodeTree(doc, m_rig->nodes, m_rig->order, why) && !matchNodes())
        why = "Assimp's node tree differs from the file's (a node tree nested deeper than " +
              std::to_string(kMaxGltfNodeDepth) + " levels?)";
    m_buffers = std::make_unique<GltfBuffers>(path, doc);
    if (why.empty()) {
        m_rig->animations = gltfAnimations(doc, *m_buffers, m_rig->nodes);
        if (!gltfSkins(doc, *m_buffers, m_rig->nodes, m_rig->skins, m_error))
            m_error = path + ": " + m_error;
        return;
    }
    // No animation of this file can be played; each says why.
    m_nodeIndex.clear();
    for (size_t a = 0; a < doc["animations"].size(); ++a) {
        Animation anim;
        const nlohmann::json& ja = doc["animations"][a];
        anim.name = ja.is_object() && ja.contains("name") && ja["name"].is_string()
                        ? ja["name"].get<std::string>()
                        : "animation " + std::to_string(a);
        anim.problem = why;
        m_rig->animations.push_back(anim);
    }
}

bool RigLoader::matchNodes() {
    const std::vector<int> roots = gltfSceneRoots(m_doc);
    const aiNode* root = m_ai.mRootNode;
    std::vector<std::pair<const aiNode*, int>> stack;
    if (roots.size() == 1) {
        stack.emplace_back(root, roots[0]);
    } else {
        if (root->mNumChildren != roots.size()) return false;
        for (size_t i = roots.size(); i-- > 0;)
            stack.emplace_back(root->mChildren[i], roots[i]);
    }
    while (!stack.empty()) {
        const auto [a, n] = stack.back();
        stack.pop_back();
        const SceneNode& node = m_rig->nodes[size_t(n)];
        const std::vector<int> children = gltfChildren(m_doc, n);
        if ((!node.name.empty() && node.name != a->mName.C_Str()) ||
            children.size() != a->mNumChildren)
            return false;
        m_nodeIndex[a] = n;
        for (size_t i = children.size(); i-- > 0;)
            stack.emplace_back(a->mChildren[i], children[i]);
    }
    return true;
}

// The first node named `name` depth first, as the loader places cameras and lights.
int RigLoader::nodeIndexNamed(const aiString& name) const {
    std::vector<const aiNode*> stack = {m_ai.mRootNode};
    while (!stack.empty()) {
        const aiNode* node = stack.back();
        stack.pop_back();
        if (node->mName == name) {
            const auto it = m_nodeIndex.find(node);
            return it != m_nodeIndex.end() ? it->second : -1;
        }
        for (unsigned i = node->mNumChildren; i-- > 0;)
            stack.push_back(node->mChildren[i]);
    }
    return -1;
}

MeshRest RigLoader::restOf(const aiMesh& am, const aiNode& node) const {
    MeshRest rest;
    if (!active()) return rest;
    const auto it = m_nodeIndex.find(&node);
    rest.node = it != m_nodeIndex.end() ? it->second : -1;
    auto vec = [](const aiVector3D& v) { return glm::vec3(v.x, v.y, v.z); };
    for (unsigned v = 0; v < am.mNumVertices; ++v) {
        rest.positions.push_back(vec(am.mVertices[v]));
        if (am.HasNormals()) rest.normals.push_back(vec(am.mNormals[v]));
        if (am.HasTangentsAndBitangents() && am.HasTextureCoords(0)) {
            rest.tangents.push_back(vec(am.mTangents[v]));
            rest.bitangents.push_back(vec(am.mBitangents[v]));
        }
    }
    return rest;
}

bool RigLoader::deformed(const MeshRest& rest, unsigned primitive) const {
    return active() && rest.node >= 0 && gltfIsDeformed(m_doc, rest.node, primitive);
}

bool RigLoader::readDeformed(Mesh& mesh, MeshRest& rest, const glm::dmat4& world,
                             unsigned primitive, std::string& error) {
    std::string why;
    bool ok = gltfMorphPrimitive(m_doc, *m_buffers, rest.node, primitive, rest, mesh, why);
    if (ok && rest.skin >= 0 && size_t(rest.skin) >= m_rig->skins.size()) {
        why = "its node's skin " + std::to_string(rest.skin) + " does not exist";
        ok = false;
    }
    // The primitive's joints exist in its skin.
    const size_t joints = ok && rest.skin >= 0 ? m_rig->skins[size_t(rest.skin)].joints.size() : 0;
    for (size_t v = 0; ok && rest.skin >= 0 && v < rest.joints.size(); ++v)
        for (int c = 0; c < 4 && ok; ++c)
            if (rest.joints[v][c] >= joints) {
                why = "JOINTS_0 names joint " + std::to_string(rest.joints[v][c]) +
                      " of a skin of " + std::to_string(joints) + " joints";
                ok = false;
            }
    if (!ok) {
        error = m_path + ": node " + std::to_string(rest.node) + ", primitive " +
                std::to_string(primitive) + " (morph targets or skin): " + why;
        return false;
    }
    std::vector<glm::dmat4> matrices;
    if (rest.skin >= 0) matrices = m_rig->jointMatrices(rest.skin, m_rig->worldTransforms({}, 0.0));
    poseMesh(rest, world, rest.weights, mesh, matrices);
    return true;
}

void RigLoader::keepMesh(MeshRest rest) {
    if (active()) m_rig->meshes.push_back(std::move(rest));
}

void RigLoader::keepCamera(const aiString& nodeName) {
    if (active()) m_rig->cameraNodes.push_back(nodeIndexNamed(nodeName));
}

void RigLoader::keepLight(const aiLight& al) {
    if (!active()) return;
    SceneRig::LightRest rest;
    rest.node = nodeIndexNamed(al.mName);
    rest.position = glm::dvec3(al.mPosition.x, al.mPosition.y, al.mPosition.z);
    rest.direction = glm::dvec3(al.mDirection.x, al.mDirection.y, al.mDirection.z);
    m_rig->lights.push_back(rest);
}

} // namespace dhdr::detail
