// Re-posing a loaded scene at time t: node transforms from the animations, composed down the
// tree, applied to the meshes, cameras and lights kept in their nodes' space.
#include <algorithm>
#include <cmath>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <glm/gtc/matrix_transform.hpp>

namespace dhdr {

glm::dmat3 normalMatrixOf(const glm::dmat4& world) {
    glm::dmat3 n = glm::transpose(glm::inverse(glm::dmat3(world)));
    double largest = 0.0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            largest = std::max(largest, std::abs(n[c][r]));
    if (largest > 0.0 && std::isfinite(largest)) n /= largest;
    return n;
}

namespace {

glm::dmat4 trs(const glm::dvec3& t, const glm::dquat& r, const glm::dvec3& s) {
    glm::dmat4 m(1.0);
    m[3] = glm::dvec4(t, 1.0);
    m = m * glm::mat4_cast(r);
    return m * glm::scale(glm::dmat4(1.0), s);
}

glm::vec3 unitOrZero(const glm::dvec3& d) {
    const double len = glm::length(d);
    return len > 1e-12 && std::isfinite(len) ? glm::vec3(d / len) : glm::vec3(0.0f);
}

// Positions that no float holds (an animation scaling by 1e39) are clamped to the largest
// float: a BVH and the G-buffer need finite numbers.
glm::vec3 finitePoint(const glm::dvec3& p) {
    const double fmax = double(std::numeric_limits<float>::max());
    glm::vec3 out;
    for (int c = 0; c < 3; ++c)
        out[c] = std::isfinite(p[c]) ? float(std::clamp(p[c], -fmax, fmax)) : 0.0f;
    return out;
}

void poseRigid(const MeshRest& rest, const glm::dmat4& world, Mesh& mesh) {
    const glm::dmat3 normalMatrix = normalMatrixOf(world), linear(world);
    for (size_t v = 0; v < rest.positions.size() && v < mesh.positions.size(); ++v)
        mesh.positions[v] = finitePoint(glm::dvec3(world * glm::dvec4(rest.positions[v], 1.0)));
    for (size_t v = 0; v < rest.normals.size() && v < mesh.normals.size(); ++v)
        mesh.normals[v] = unitOrZero(normalMatrix * glm::dvec3(rest.normals[v]));
    for (size_t v = 0; v < rest.tangents.size() && v < mesh.tangents.size(); ++v) {
        mesh.tangents[v] = unitOrZero(linear * glm::dvec3(rest.tangents[v]));
        mesh.bitangents[v] = unitOrZero(linear * glm::dvec3(rest.bitangents[v]));
    }
}

// The vertices of `rest` morphed by `weights` (node space), and their normals when the file
// gives them (else each triangle's of `mesh`, flat).
void morphedVertices(const MeshRest& rest, const Mesh& mesh, const std::vector<double>& weights,
                     std::vector<glm::dvec3>& positions, std::vector<glm::dvec3>& normals) {
    const size_t count = rest.positions.size();
    positions.assign(count, glm::dvec3(0.0));
    for (size_t i = 0; i < count; ++i)
        positions[i] = glm::dvec3(rest.positions[i]);
    for (size_t t = 0; t < rest.positionTargets.size() && t < weights.size(); ++t)
        if (weights[t] != 0.0)
            for (size_t i = 0; i < count; ++i)
                positions[i] += weights[t] * glm::dvec3(rest.positionTargets[t][i]);
    normals.assign(count, glm::dvec3(0.0));
    if (!rest.flatNormals) {
        for (size_t i = 0; i < count && i < rest.normals.size(); ++i)
            normals[i] = glm::dvec3(rest.normals[i]);
        for (size_t t = 0; t < rest.normalTargets.size() && t < weights.size(); ++t)
            if (weights[t] != 0.0)
                for (size_t i = 0; i < count; ++i)
                    normals[i] += weights[t] * glm::dvec3(rest.normalTargets[t][i]);
        return;
    }
    // No normals in the file: the vertices are the triangles' own (gltfMorphPrimitive), each
    // with its triangle's normal.
    for (const glm::uvec3& tri : mesh.triangles) {
        const glm::dvec3 n =
            glm::cross(positions[tri.y] - positions[tri.x], positions[tri.z] - positions[tri.x]);
        normals[tri.x] = normals[tri.y] = normals[tri.z] = n;
    }
}

} // namespace

void poseMesh(const MeshRest& rest, const glm::dmat4& world, const std::vector<double>& weights,
              Mesh& mesh, const std::vector<glm::dmat4>& jointMatrices) {
    const bool skinned = rest.skin >= 0 && !jointMatrices.empty();
    if (rest.positionTargets.empty() && !skinned) return poseRigid(rest, world, mesh);
    // Morph first, then skin (or the node's transform).
    std::vector<glm::dvec3> positions, normals;
    morphedVertices(rest, mesh, weights, positions, normals);
    const glm::dmat3 normalMatrix = normalMatrixOf(world);
    for (size_t v = 0; v < positions.size() && v < mesh.positions.size(); ++v) {
        glm::dmat4 m = world;
        if (skinned) {
            // Σ wₖ Jₖ; weights that sum to 0 leave the vertex where its node puts it.
            glm::dmat4 sum(0.0);
            double total = 0.0;
            for (int c = 0; c < 4; ++c) {
                const double w = double(rest.jointWeights[v][c]);
                if (w == 0.0) continue;
                sum += w * jointMatrices[rest.joints[v][c]];
                total += w;
            }
            if (total != 0.0) m = sum;
        }
        mesh.positions[v] = finitePoint(glm::dvec3(m * glm::dvec4(positions[v], 1.0)));
        mesh.normals[v] = unitOrZero((skinned ? normalMatrixOf(m) : normalMatrix) * normals[v]);
    }
}

std::vector<glm::dmat4> SceneRig::jointMatrices(int skin,
                                                const std::vector<glm::dmat4>& world) const {
    const SceneSkin& s = skins[size_t(skin)];
    std::vector<glm::dmat4> out(s.joints.size());
    for (size_t j = 0; j < s.joints.size(); ++j)
        out[j] = world[size_t(s.joints[j])] * s.inverseBind[j];
    return out;
}

std::vector<glm::dmat4> SceneRig::worldTransforms(const std::vector<int>& playing, double t) const {
    std::vector<glm::dvec3> translation(nodes.size()), scale(nodes.size());
    std::vector<glm::dquat> rotation(nodes.size());
    for (size_t n = 0; n < nodes.size(); ++n) {
        translation[n] = nodes[n].translation;
        rotation[n] = nodes[n].rotation;
        scale[n] = nodes[n].scale;
    }
    std::vector<char> animated(nodes.size(), 0);
    for (const int a : playing) {
        const Animation& anim = animations[size_t(a)];
        for (const AnimationChannel& ch : anim.channels) {
            if (ch.property == AnimatedProperty::Weights) continue; // morph targets: not applied
            double v[4] = {0.0, 0.0, 0.0, 1.0};
            anim.samplers[size_t(ch.sampler)].evaluate(t, v);
            const size_t n = size_t(ch.node);
            animated[n] = 1;
            if (ch.property == AnimatedProperty::Translation) translation[n] = {v[0], v[1], v[2]};
            if (ch.property == AnimatedProperty::Rotation)
                rotation[n] = glm::dquat(v[3], v[0], v[1], v[2]);
            if (ch.property == AnimatedProperty::Scale) scale[n] = {v[0], v[1], v[2]};
        }
    }
    std::vector<glm::dmat4> world(nodes.size(), glm::dmat4(1.0));
    for (const int n : order) {
        const SceneNode& node = nodes[size_t(n)];
        const glm::dmat4 local =
            node.hasMatrix && !animated[size_t(n)]
                ? node.matrix
                : trs(translation[size_t(n)], rotation[size_t(n)], scale[size_t(n)]);
        world[size_t(n)] = node.parent >= 0 ? world[size_t(node.parent)] * local : local;
    }
    return world;
}

bool SceneRig::weightsAt(const std::vector<int>& playing, int node, double t,
                         std::vector<double>& weights) const {
    bool found = false;
    for (const int a : playing)
        for (const AnimationChannel& ch : animations[size_t(a)].channels) {
            if (ch.property != AnimatedProperty::Weights || ch.node != node) continue;
            const AnimationSampler& s = animations[size_t(a)].samplers[size_t(ch.sampler)];
            std::vector<double> w(size_t(s.components), 0.0);
            s.evaluate(t, w.data());
            weights = std::move(w);
            found = true;
        }
    return found;
}

std::vector<int> SceneRig::movingMeshes(const std::vector<int>& playing) const {
    const std::vector<bool> moved = animatedNodes(playing);
    std::vector<bool> morphed(nodes.size(), false);
    for (const int a : playing)
        for (const AnimationChannel& ch : animations[size_t(a)].channels)
            if (ch.property == AnimatedProperty::Weights) morphed[size_t(ch.node)] = true;
    std::vector<int> out;
    for (size_t i = 0; i < meshes.size(); ++i) {
        const int n = meshes[i].node;
        bool skinMoves = false;
        if (meshes[i].skin >= 0)
            for (const int j : skins[size_t(meshes[i].skin)].joints)
                skinMoves = skinMoves || moved[size_t(j)];
        if (n >= 0 && (moved[size_t(n)] || skinMoves ||
                       (morphed[size_t(n)] && !meshes[i].positionTargets.empty())))
            out.push_back(int(i));
    }
    return out;
}

std::vector<bool> SceneRig::animatedNodes(const std::vector<int>& playing) const {
    std::vector<bool> out(nodes.size(), false);
    for (const int a : playing)
        for (const AnimationChannel& ch : animations[size_t(a)].channels)
            if (ch.property != AnimatedProperty::Weights) out[size_t(ch.node)] = true;
    for (const int n : order)
        if (nodes[size_t(n)].parent >= 0 && out[size_t(nodes[size_t(n)].parent)])
            out[size_t(n)] = true;
    return out;
}

ScenePoser::ScenePoser(Scene& scene, std::vector<int> playing)
    : m_scene(scene), m_playing(std::move(playing)) {
    if (!m_scene.rig) return;
    m_animated = m_scene.rig->animatedNodes(m_playing);
    for (const int i : m_scene.rig->movingMeshes(m_playing))
        m_moving.push_back(i);
}

void ScenePoser::pose(double t, std::vector<int>* changed) {
    if (changed) changed->clear();
    if (!m_scene.rig) return;
    const SceneRig& rig = *m_scene.rig;
    const std::vector<glm::dmat4> world = rig.worldTransforms(m_playing, t);
    m_applied.resize(m_scene.meshes.size(), glm::dmat4(1.0));
    m_appliedWeights.resize(m_scene.meshes.size());
    // Only what moves is touched (the rest keeps the loader's numbers bit for bit), and of that
    // only what moved since the last pose, so that the ray caster refits only those meshes.
    for (const int i : m_moving) {
        const MeshRest& rest = rig.meshes[size_t(i)];
        const glm::dmat4& w = world[size_t(rest.node)];
        std::vector<double> weights = rest.weights;
        if (!rest.positionTargets.empty()) rig.weightsAt(m_playing, rest.node, t, weights);
        // A skinned mesh follows its joints: posed every time.
        std::vector<glm::dmat4> joints;
        if (rest.skin >= 0)
            joints = rig.jointMatrices(rest.skin, world);
        else if (!m_first && w == m_applied[size_t(i)] && weights == m_appliedWeights[size_t(i)])
            continue;
        poseMesh(rest, w, weights, m_scene.meshes[size_t(i)], joints);
        // Moved as a whole: the ray caster moves an instance of its rest triangles.
        if (rest.skin < 0 && rest.positionTargets.empty()) m_scene.meshes[size_t(i)].instance = w;
        m_applied[size_t(i)] = w;
        m_appliedWeights[size_t(i)] = std::move(weights);
        if (changed) changed->push_back(i);
    }
    m_first = false;
    for (size_t i = 0; i < m_scene.cameras.size() && i < rig.cameraNodes.size(); ++i)
        if (rig.cameraNodes[i] >= 0 && m_animated[size_t(rig.cameraNodes[i])])
            m_scene.cameras[i].camera.cameraToWorld = world[size_t(rig.cameraNodes[i])];
    for (size_t i = 0; i < m_scene.lights.size() && i < rig.lights.size(); ++i) {
        const SceneRig::LightRest& l = rig.lights[i];
        if (l.node < 0 || !m_animated[size_t(l.node)]) continue;
        const glm::dmat4& w = world[size_t(l.node)];
        m_scene.lights[i].position = glm::vec3(w * glm::dvec4(l.position, 1.0));
        const glm::dvec3 dir(w * glm::dvec4(l.direction, 0.0));
        m_scene.lights[i].direction =
            glm::length(dir) > 0.0 ? glm::vec3(glm::normalize(dir)) : glm::vec3(0.0f, 0.0f, -1.0f);
    }
}

} // namespace dhdr
