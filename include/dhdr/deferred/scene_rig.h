// What it takes to re-pose a loaded scene at another time without loading it again: the glTF
// file's node tree with each node's rest transform, its animations, and the node each mesh,
// camera and light hangs from with their data in that node's space (docs/animation.md).
#pragma once

#include <dhdr/deferred/animation.h>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
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
};

struct SceneRig {
    std::vector<SceneNode> nodes;
    std::vector<int> order; // node indices, every parent before its children
    std::vector<Animation> animations;
    std::vector<MeshRest> meshes; // one per Scene::meshes entry
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
};

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
    std::vector<glm::dmat4> m_applied; // the world transform each mesh was last posed with
    bool m_first = true;
};

} // namespace dhdr
