// What Debian's Assimp 5.2 drops from glTF files, read from the file's own JSON.
#pragma once

#include <dhdr/deferred/scene/scene.h>
#include <glm/glm.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

namespace dhdr::detail {

// The JSON document of a .gltf or .glb file, read once by loadScene and handed to the readers
// below; discarded when the file is neither.
nlohmann::json gltfJson(const std::string& path);

// The JSON chunk of a binary glTF's bytes (12-byte header, then chunk length, chunk type
// "JSON"); empty for other bytes.
std::string glbJsonChunk(const std::vector<char>& bytes);

// KHR_materials_emissive_strength per material name, from a .gltf or .glb file. Empty for
// other files, or when no material uses the extension.
std::map<std::string, float> gltfEmissiveStrengths(const nlohmann::json& doc);

// KHR_materials_specular of a material (Assimp 5.2 does not read it): its factors, and its
// textures' textureInfo objects as the file writes them (null where absent; read by
// readMaterials, which resolves them to images itself).
struct GltfSpecular {
    float factor = 1.0f;
    glm::vec3 color{1.0f};
    nlohmann::json texture, colorTexture;
};

// Per material name, for the materials that use it; empty for other files.
std::map<std::string, GltfSpecular> gltfSpecular(const nlohmann::json& doc);

// KHR_materials_pbrSpecularGlossiness of a material: its factors, clamped to the schema's
// [0, 1] (a value that is no number keeps the default), and which textures it names.
struct GltfSpecGloss {
    glm::vec4 diffuse{1.0f};
    glm::vec3 specular{1.0f};
    float glossiness = 1.0f;
    // The textures' textureInfo objects as the file writes them (null where absent): Assimp 5.2
    // reports them only when extensionsUsed names the extension, dhdr reads them from here.
    nlohmann::json diffuseTexture, specularGlossinessTexture;
};

// Per material name, for the materials that use it; empty for other files.
std::map<std::string, GltfSpecGloss> gltfSpecGloss(const nlohmann::json& doc);

// What Assimp 5.2 does not report of a glTF material's texture reference: its
// KHR_texture_transform, and the UV set that extension's `texCoord` overrides the
// reference's with (−1: none).
struct GltfTextureInfo {
    TextureTransform transform;
    int texCoord = -1;
};

// Those of each texture slot of a material.
struct GltfMaterialTextures {
    GltfTextureInfo baseColor, emissive, normal, metallicRoughness, occlusion;
    GltfTextureInfo clearcoat, clearcoatRoughness, clearcoatNormal;
    GltfTextureInfo sheenColor, sheenRoughness;
    GltfTextureInfo specular, specularColor;     // KHR_materials_specular's
    GltfTextureInfo diffuse, specularGlossiness; // KHR_materials_pbrSpecularGlossiness's
    GltfTextureInfo transmission;                // KHR_materials_transmission's
};

// Per material name, from a .gltf or .glb file; empty for other files.
std::map<std::string, GltfMaterialTextures> gltfMaterialTextures(const nlohmann::json& doc);

// Whether a primitive of the file has a COLOR_0 accessor of type VEC3 (RGB, no alpha).
bool gltfHasRgbVertexColors(const nlohmann::json& doc);

// What the file uses that dhdr leaves out, one line each: extensions whose effect does not
// reach the render (from extensionsUsed), skins and morph targets (the rest pose is rendered),
// texture references to a UV set past the second.
std::vector<std::string> gltfIgnoredFeatures(const nlohmann::json& doc);

// Whether what the extension `name` says reaches the render of the glTF file `doc`, read
// by Assimp 5.2 or by dhdr from the JSON (the lists differ between glTF 1.0 and 2.0).
bool gltfExtensionRendered(const nlohmann::json& doc, const std::string& name);

// The extensions each material names (the keys of its "extensions", sorted), by material name;
// materials without a name or extensions are left out.
std::map<std::string, std::vector<std::string>> gltfMaterialExtensions(const nlohmann::json& doc);

// Why Assimp 5.2 cannot read a Draco-compressed primitive of the file: it drops the indices it
// decodes when they are 32-bit ("Invalid accessor without data"); empty when none is such.
std::string gltfDracoIndexProblem(const nlohmann::json& doc);

// The animations of a glTF 1.0 file, which Assimp 5.2 drops and dhdr does not play; 0 for
// glTF 2.0 files, whose animations dhdr reads itself.
size_t gltfUnplayedAnimations(const nlohmann::json& doc);

// Why a glTF file Assimp loads without a message holds nothing to render ("its scene has no
// nodes"); empty when the file does not say.
std::string gltfEmptySceneReason(const nlohmann::json& doc);

// A KHR_lights_punctual light as the file gives it (Assimp 5.2 folds the intensity into the
// colour and drops the range).
struct GltfLight {
    std::string type = "point";
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    float range = 0.0f; // 0: none given
    float innerConeAngle = 0.0f, outerConeAngle = 0.7853982f;
};

// The lights of a .gltf or .glb file by the name of the node that holds them. False, with
// `error` naming the light and field, when a field has the wrong type or does not fit a float
// (Assimp accepts such files).
bool gltfLightsByNode(const nlohmann::json& doc, std::map<std::string, GltfLight>& lights,
                      std::string& error);

// A glTF camera as the file gives it: Assimp 5.2 passes its numbers through floats and
// folds the aspect ratio into the field of view, and reports an absent zfar as a number.
struct GltfCamera {
    std::string name; // the camera's own name, for messages
    bool orthographic = false;
    double yfov = 0.0, aspectRatio = 0.0; // perspective; aspectRatio 0: none given
    double xmag = 0.0, ymag = 0.0;        // orthographic
    double znear = 0.0, zfar = 0.0;       // zfar 0: none given (perspective)
    std::string problem; // a field of the wrong type, or missing: the camera is unusable
};

// The cameras of a .gltf or .glb file by the name of the node that holds them (unnamed nodes
// are left out).
std::map<std::string, GltfCamera> gltfCamerasByNode(const nlohmann::json& doc);

// The names the file gives the elements of its top-level array `array` ("nodes", "meshes"):
// Assimp 5.2 names an unnamed one after its place ("nodes[3]"), which is no name to show.
std::set<std::string> gltfNames(const nlohmann::json& doc, const char* array);

// What Assimp 5.2 is handed of a glTF file (gltf_for_assimp.cpp).

// Assimp 5.2 reads a glTF node tree recursively, and its stack overflows on a few thousand
// levels: nodes nested deeper than this are handed to it flattened.
inline constexpr int kMaxGltfNodeDepth = 256;

// When the node tree of the .gltf or .glb file at `path` (its JSON `doc`) nests deeper than
// kMaxGltfNodeDepth, the file's bytes with the default scene's nodes flattened (each node's world
// transform as its matrix, no children, all of them the scene's roots, in depth-first order) in
// `bytes`; else `bytes` empty. Walks the tree with an explicit stack. False, with `error`, when the
// nodes do not form a tree (a node its own ancestor, which Assimp would recurse on forever, or
// reached twice in a tree it must flatten).
bool gltfFlattenDeepNodes(const std::string& path, const nlohmann::json& doc, std::string& bytes,
                          std::string& error);

// What Assimp is handed of a glTF file's JSON: dhdr reads animations and skins itself, and
// Assimp 5.2 gets them wrong (it makes STEP and CUBICSPLINE linear, crashes on a skin without
// inverseBindMatrices, and its validation refuses files for mistakes in animations with
// messages about its own structures), so `doc` without `animations`, `skins` and the nodes'
// `skin` (docs/scenes.md).
bool gltfHasAnimationOrSkins(const nlohmann::json& doc);
nlohmann::json gltfForAssimp(nlohmann::json doc);

// The bytes of the .gltf or .glb file at `path` with `doc` as its JSON (a .glb keeps its other
// chunks as they are).
std::string gltfBytesWithJson(const std::string& path, const nlohmann::json& doc);

} // namespace dhdr::detail
