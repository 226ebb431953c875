// What it takes to re-pose a loaded scene at another time without loading it again: the glTF
// file's node tree with each node's rest transform, its animations, and the node each mesh,
// camera and light hangs from with their data in that node's space (docs/animation.md).
#pragma once

#include <dhdr/deferred/scene/animation.h>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_precision.hpp>
#include <string>
#include <vector>

namespace dhdr {

struct Scene;

struct SceneNode {
    std::string name;
    int parent = -1;
    bool hasMatrix = false; // a node given by a matrix (glTF: it cannot be animated)
    glm::dmat4 matrix{1.0};
    glm::dvec3 translation{0.0};
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0}; // w, x, y, z
    glm::dvec3 scale{1.0};
};

// A mesh's vertices in the space of its node (the file's numbers), so that the world positions
// at any time are that node's world transform applied to them, as the loader applies it.
struct MeshRest {
    int node = -1; // −1: the mesh does not move
    std::vector<glm::vec3> positions, normals, tangents, bitangents;
    // Morph targets (a glTF primitive with `targets`, read from the file): per target one
    // position delta per vertex (and normal deltas, or none); the vertex is
    // base + Σ wᵢ Δᵢ in the node's space, before the node's transform (docs/animation.md).
    std::vector<std::vector<glm::vec3>> positionTargets, normalTargets;
    std::vector<double> weights; // the default weights: the node's, else the mesh's, else 0
    bool flatNormals = false;    // no NORMAL in the file: each triangle's, from posed positions
    // A skinned primitive: its skin (index into SceneRig::skins, −1: none), and per vertex four
    // joints (indices into the skin's joints) and their weights. The vertex is
    // Σ wₖ · world(jointₖ) · inverseBind(jointₖ) · (morphed vertex); the node's own transform
    // is ignored (glTF 2.0 §3.7.3).
    int skin = -1;
    std::vector<glm::u16vec4> joints;
    std::vector<glm::vec4> jointWeights;
};

// A glTF skin: its joints (node indices) and their inverse bind matrices (identity when the
// file gives none).
struct SceneSkin {
    std::vector<int> joints;
    std::vector<glm::dmat4> inverseBind;
};

struct SceneRig {
    std::vector<SceneNode> nodes;
    std::vector<int> order; // node indices, every parent before its children
    std::vector<Animation> animations;
    std::vector<MeshRest> meshes; // one per Scene::meshes entry
    std::vector<SceneSkin> skins;
    std::vector<int> cameraNodes; // one per Scene::cameras entry; −1: it does not move
    struct LightRest {
        int node = -1;
        glm::dvec3 position{0.0}, direction{0.0, 0.0, -1.0}; // in the node's space
    };
    std::vector<LightRest> lights; // one per Scene::lights entry

    // Every node's world transform at time `t` (seconds) with the animations `playing`
    // (indices into `animations`) applied: T · R · S of each node with the animated properties
    // replaced by their values at t, composed down the tree.
    std::vector<glm::dmat4> worldTransforms(const std::vector<int>& playing, double t) const;
    // Whether node `n` or one of its ancestors is driven by one of `playing`.
    std::vector<bool> animatedNodes(const std::vector<int>& playing) const;
    // The morph target weights of node `node` at time t: its default weights with those of the
    // animations `playing` that drive them; false (and `weights` untouched) when none does.
    bool weightsAt(const std::vector<int>& playing, int node, double t,
                   std::vector<double>& weights) const;
    // The joint matrices world(jointₖ) · inverseBind(jointₖ) of skin `skin` given every node's
    // world transform.
    std::vector<glm::dmat4> jointMatrices(int skin, const std::vector<glm::dmat4>& world) const;
    // The meshes that `playing` moves: under an animated node, morphed by animated weights, or
    // skinned to an animated joint.
    std::vector<int> movingMeshes(const std::vector<int>& playing) const;
};

// Sets `mesh`'s vertices, normals and tangents to those of `rest` morphed by `weights` (when it
// has targets), then skinned by `jointMatrices` (when it has a skin) or else moved by its node's
// world transform `world`.
struct Mesh;
void poseMesh(const MeshRest& rest, const glm::dmat4& world, const std::vector<double>& weights,
              Mesh& mesh, const std::vector<glm::dmat4>& jointMatrices = {});

// Moves a scene that loadScene gave a rig to time `t`: the vertices, normals and tangents of
// its meshes, its cameras and its lights, those that the animations `playing` move (the others
// keep the loader's numbers). The indices of the meshes whose vertices changed since the last
// call (all that move, the first time) go to `changed`.
class ScenePoser {
public:
    ScenePoser(Scene& scene, std::vector<int> playing);
    void pose(double t, std::vector<int>* changed = nullptr);

private:
    Scene& m_scene;
    std::vector<int> m_playing;
    std::vector<bool> m_animated;      // per node: moved by `playing`
    std::vector<int> m_moving;         // the meshes `playing` moves
    std::vector<glm::dmat4> m_applied; // the world transform each mesh was last posed with
    std::vector<std::vector<double>> m_appliedWeights; // and its morph weights
    bool m_first = true;
};

// The normal matrix of a node's world transform: the inverse transpose, scaled to its largest
// entry, so that a node scaled by 1e38 keeps usable normals (only their direction matters).
glm::dmat3 normalMatrixOf(const glm::dmat4& world);

} // namespace dhdr
