// A scene flattened for primary-ray casting: triangle meshes in world space, glTF
// metallic-roughness materials, cameras and punctual lights.
#pragma once

#include <dhdr/deferred/camera.h>
#include <dhdr/deferred/lights.h>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace dhdr {

// A base-colour texture decoded to linear RGBA float.
struct Texture {
    std::string name;
    int width = 0, height = 0;
    std::vector<float> rgba;

    // Bilinear lookup with repeat wrapping, glTF's default sampler; uv (0, 0) is the top-left.
    glm::vec4 sample(glm::vec2 uv) const;
};

struct Material {
    std::string name;
    glm::vec3 baseColor{1.0f}; // linear
    float alpha = 1.0f;
    float roughness = 1.0f;
    float metallic = 1.0f;     // glTF defaults: a material without these is rough metal
    glm::vec3 emission{0.0f};  // linear radiance: emissiveFactor × emissive strength
    int baseColorTexture = -1; // index into Scene::textures
};

struct Mesh {
    std::vector<glm::vec3> positions; // world space
    std::vector<glm::vec3> normals;   // world space, unit
    std::vector<glm::vec2> uvs;       // origin at the image's top-left, as glTF; may be empty
    std::vector<glm::uvec3> triangles;
    int material = 0;
    int object = 0; // index into Scene::objectNames
};

struct SceneCamera {
    std::string name;
    Camera camera;
    double aspect = 0.0; // width / height from the file, 0 when unknown
};

struct Scene {
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<std::string> objectNames;
    std::vector<SceneCamera> cameras;
    std::vector<Light> lights; // world space, KHR_lights_punctual units
    // What the loader repaired or left out, one line each, for the tool to print.
    std::vector<std::string> warnings;

    glm::dvec3 boundsMin() const;
    glm::dvec3 boundsMax() const;
};

// Loads a glTF 2.0 (.gltf, .glb) or OBJ file through Assimp: triangulated, with smooth normals
// where the file has none, node transforms applied. Works around Assimp 5.2's glTF quirks
// (docs/scenes.md). On failure returns false with a message in `error`.
bool loadScene(const std::string& path, Scene& scene, std::string& error);

} // namespace dhdr
