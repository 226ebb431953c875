// A scene flattened for primary-ray casting: triangle meshes in world space, glTF
// metallic-roughness materials, cameras and punctual lights.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <dhdr/deferred/scene/camera.h>
#include <dhdr/deferred/scene/lights.h>
#include <dhdr/deferred/scene/texture.h>
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dhdr {

struct SceneRig;

// How a material's alpha is used (glTF 2.0 §3.9.4 alphaMode).
enum class AlphaMode {
    Opaque, // alpha ignored
    Mask,   // a surface where alpha ≥ alphaCutoff, none elsewhere (cut-outs)
    Blend   // a partly transparent surface of coverage alpha
};

struct Material {
    std::string name;
    glm::vec3 baseColor{1.0f}; // linear
    float alpha = 1.0f;        // baseColorFactor.a (glTF), d or 1 − Tr (OBJ)
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f; // Mask only, glTF's default
    float roughness = 1.0f;
    float metallic = 1.0f;       // glTF defaults: a material without these is rough metal
    glm::vec3 emission{0.0f};    // linear radiance: emissiveFactor × emissive strength
    TextureRef baseColorTexture; // sRGB-encoded, multiplies baseColor
    TextureRef emissiveTexture;  // sRGB-encoded, multiplies emission
    TextureRef normalTexture;    // linear, tangent space (+X along u, +Y up the image)
    float normalScale = 1.0f;    // glTF normalTexture.scale: scales the map's X and Y
    // Linear; B scales metallic and G roughness (glTF 2.0 §3.9.2).
    TextureRef metallicRoughnessTexture;
    // Linear; R is the ambient occlusion, applied as 1 + strength · (R − 1) (§3.9.3).
    TextureRef occlusionTexture;
    float occlusionStrength = 1.0f;
    // The dielectric layer (KHR_materials_ior, KHR_materials_specular): its index of
    // refraction, and the specular factor and colour that scale its reflectance, each × its
    // texture (specularTexture's A, linear; specularColorTexture's RGB, sRGB).
    float ior = 1.5f;
    float specularFactor = 1.0f;
    glm::vec3 specularColor{1.0f};
    TextureRef specularTexture, specularColorTexture;
    // The file sets any of them (or `unlit`): the G-buffer carries the dielectric's
    // reflectance (its specular channels).
    bool dielectricSet = false;
    // KHR_materials_unlit: the base colour is what the surface shows, lit by nothing.
    bool unlit = false;
    // KHR_materials_clearcoat: the coat's weight (0: none) and roughness, each × its texture
    // (R and G, linear), and the coat's own normal map (none: the coat follows the interpolated
    // normal, not the base's normal map).
    float clearcoat = 0.0f, clearcoatRoughness = 0.0f;
    TextureRef clearcoatTexture, clearcoatRoughnessTexture, clearcoatNormalTexture;
    float clearcoatNormalScale = 1.0f;
    // KHR_materials_sheen: the sheen's colour (0: none; × its texture's RGB, sRGB) and
    // roughness (× its texture's A, linear).
    glm::vec3 sheenColor{0.0f};
    float sheenRoughness = 0.0f;
    TextureRef sheenColorTexture, sheenRoughnessTexture;
    bool sheen() const { return std::max({sheenColor.r, sheenColor.g, sheenColor.b}) > 0.0f; }
    // KHR_materials_transmission: the share of the dielectric's base that passes through (0:
    // opaque; × its texture's R, linear), thin walled (no refraction).
    float transmission = 0.0f;
    TextureRef transmissionTexture;
    // KHR_materials_volume: the medium inside (thickness above 0) absorbs as Beer's law with
    // attenuationColor^(d / attenuationDistance) over a distance d; an infinite distance: none.
    float thickness = 0.0f;
    float attenuationDistance = INFINITY;
    glm::vec3 attenuationColor{1.0f};
    bool absorbs() const {
        return transmission > 0.0f && thickness > 0.0f && std::isfinite(attenuationDistance) &&
               attenuationColor != glm::vec3(1.0f);
    }
    // KHR_materials_pbrSpecularGlossiness's specularGlossinessTexture (RGB the specular colour,
    // sRGB; A the glossiness, linear). The material is converted to metal-rough when it is read
    // (specGlossAsMetalRough); with this texture the conversion is made per texel instead, from
    // baseColor (then the diffuse colour, undimmed) and the two factors the texel scales.
    TextureRef specularGlossinessTexture;
    glm::vec3 glossSpecular{1.0f};
    float glossiness = 1.0f;

    // KHR_materials_specular's dielectric_f0: min(((ior − 1) / (ior + 1))² · specularColor, 1)
    // · specularFactor; 4 % when the file sets none of them.
    glm::vec3 dielectricF0() const;
    // Its f90: specularFactor.
    float dielectricF90() const { return dielectricSet ? specularFactor : 1.0f; }
};

// KHR_materials_specular's dielectric_f0 (its README, "Implementation", with KHR_materials_ior):
// min(((ior − 1) / (ior + 1))² · specularColor, 1) · specular, where each of specular and
// specularColor is the factor × its texture.
glm::vec3 dielectricF0(float ior, const glm::vec3& specularColor, float specular);

// KHR_materials_pbrSpecularGlossiness's BRDF inputs (its README, "Specular - Glossiness":
// c_diff = diffuse · (1 − max(specular)), F0 = specular, α = (1 − glossiness)²) as the
// metal-rough model: metallic 0, the base colour c_diff, roughness 1 − glossiness (α = r²), and
// a dielectric of F0 = specular and F90 = 1.
struct MetalRoughFromSpecGloss {
    glm::vec3 baseColor;
    float roughness;
    glm::vec3 f0;
};
MetalRoughFromSpecGloss specGlossAsMetalRough(const glm::vec3& diffuse, const glm::vec3& specular,
                                              float glossiness);

struct Mesh {
    std::vector<glm::vec3> positions; // world space
    std::vector<glm::vec3> normals;   // world space, unit; zero where the file's was unusable
    std::vector<glm::vec2> uvs;       // origin at the image's top-left, as glTF; may be empty
    std::vector<glm::vec2> uvs1;      // the second UV set (TEXCOORD_1), the same; may be empty
    // Vertex colours (glTF COLOR_0, linear RGBA): they multiply the base colour and its alpha;
    // may be empty.
    std::vector<glm::vec4> colors;
    // World-space tangent (along +u) and bitangent (up the image) per vertex, from the file
    // or generated from the UVs; empty without UVs.
    std::vector<glm::vec3> tangents, bitangents;
    std::vector<glm::uvec3> triangles;
    int material = 0;
    int object = 0; // index into Scene::objectNames
    // A mesh that an animation moves as a whole (no skin, no morph targets): its node's world
    // transform, which placed its node-space vertices (SceneRig::meshes) at `positions`. Set by
    // ScenePoser; the ray caster traces such a mesh as an instance moved by this transform, and
    // its points' error bound carries the transform's rounding (positionError). Unset: the
    // mesh is traced as it lies.
    std::optional<glm::dmat4> instance;
};

struct SceneCamera {
    std::string name;
    Camera camera;
    double aspect = 0.0; // width / height from the file, 0 when unknown
    // Why the camera cannot be rendered from (a node scaled by 0, a field of view of 0, a
    // field of the wrong type...), empty when it can; the tools refuse it by this message.
    std::string problem;
};

// An extension a glTF material names, and whether what it says reaches the render.
struct MaterialExtension {
    std::string name;
    bool rendered = false;
};

struct Scene {
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    // The glTF extensions each material names, by index into materials (--info, the Python
    // module's Scene.materials); materials that name none are absent.
    std::map<int, std::vector<MaterialExtension>> materialExtensions;
    std::vector<Texture> textures;
    std::vector<std::string> objectNames;
    std::vector<SceneCamera> cameras;
    std::vector<Light> lights; // world space, KHR_lights_punctual units
    // What the loader repaired or left out, one line each, for the tool to print.
    std::vector<std::string> warnings;
    // An infinite horizontal plane y = groundPlaneY under everything, intersected exactly (not
    // a mesh): the shadow catcher of AR compositing (addGroundPlane, docs/ibl.md).
    bool hasGroundPlane = false;
    float groundPlaneY = 0.0f;
    int groundObject = -1, groundMaterial = -1; // indices into objectNames and materials
    // A glTF file with animations: its node tree, animations and the meshes' rest data, for
    // ScenePoser (scene_rig.h); null for other files, whose scene never moves.
    std::shared_ptr<const SceneRig> rig;

    glm::dvec3 boundsMin() const;
    glm::dvec3 boundsMax() const;
};

// A pixel's footprint on a surface's UV sets: per set, the change of uv from the pixel to its
// neighbour across (dx) and down (dy), and how lookups filter over it (uvDifferentials()).
struct UvFootprint {
    glm::vec2 dx[2] = {glm::vec2(0.0f), glm::vec2(0.0f)};
    glm::vec2 dy[2] = {glm::vec2(0.0f), glm::vec2(0.0f)};
    TextureFilter filter = TextureFilter::Trilinear;
};

// A triangle's UV sets at barycentrics (w1, w2): set[0] from Mesh::uvs, set[1] from
// Mesh::uvs1 (set[0] where the mesh has no second set); zero where it has none. With a
// footprint, lookups are filtered over it; without, each is one bilinear lookup.
struct MeshUvs {
    glm::vec2 set[2] = {glm::vec2(0.0f), glm::vec2(0.0f)};
    const UvFootprint* footprint = nullptr;
};
MeshUvs meshUvs(const Mesh& mesh, int triangle, double w1, double w2);

// `ref`'s texture (ref.texture ≥ 0) at the UVs of its set, transformed and wrapped as it says.
glm::vec4 sampleTexture(const Scene& scene, const TextureRef& ref, const MeshUvs& uvs);
// Whether that lookup reads `ref`'s mip levels (Texture::minified).
bool textureMinified(const Scene& scene, const TextureRef& ref, const MeshUvs& uvs);

// The mesh's vertex colour at barycentrics (w1, w2) of a triangle; 1 without vertex colours.
glm::vec4 vertexColor(const Mesh& mesh, int triangle, double w1, double w2);

// The alpha of a mesh's surface at barycentrics (u, v) of a triangle: the material's alpha
// times its vertex colour's and its base colour texture's alpha there.
float surfaceAlpha(const Scene& scene, int mesh, int triangle, float u, float v);

// Whether a hit on that surface is a surface at all (false: a Mask material cut out there),
// and its coverage in [0, 1] (1 unless the material blends).
struct SurfaceCoverage {
    bool present = true;
    float alpha = 1.0f;
};
SurfaceCoverage surfaceCoverage(const Scene& scene, int mesh, int triangle, float u, float v);

// The name the ground plane has among the objects (and materials) of a G-buffer.
inline constexpr const char* kGroundPlaneName = "dhdr:ground plane";

// Adds the infinite ground plane at height y: an object and a white rough material of that
// name (RGB 0.8, roughness 1).
void addGroundPlane(Scene& scene, float y);

// A camera like `like` (its direction, up and projection) moved so that the scene's bounding
// sphere just fits an image of `aspect` (width / height): perspective cameras back off along
// their view axis, orthographic ones also widen their image plane. Check the result with
// Camera::problem(): bounds too large for a float camera give one that cannot be used.
Camera frameScene(const Scene& scene, const Camera& like, double aspect);
// The same for the box from `lo` to `hi` (an animation's whole span, framed once for its frames).
Camera frameBounds(const glm::dvec3& lo, const glm::dvec3& hi, const Camera& like, double aspect);

// How loadScene treats what it could repair.
struct SceneOptions {
    // A texture that cannot be read (missing, undecodable): false, a warning in
    // Scene::warnings naming the texture and the material, whose texture is then magenta
    // (1, 0, 1) times its factor, as Blender shows a missing texture (a normal map is left out);
    // true, an error (the tools' --strict).
    bool strict = false;
};

// Loads a glTF 2.0 (.gltf, .glb) or OBJ file through Assimp: triangulated, with flat normals
// where the file has none, node transforms applied. Works around Assimp 5.2's glTF quirks
// (docs/scenes.md). On failure returns false with a message in `error`.
bool loadScene(const std::string& path, Scene& scene, std::string& error,
               const SceneOptions& options = {});

// SHA-1 of the bytes of the scene file at `path` (40 hex digits), the fingerprint dhdr-gbuffer
// records in the G-buffer (gbuffer::kSceneFingerprint) so that dhdr-light can tell whether
// --scene names the file the G-buffer was rendered from. Empty when the file cannot be read.
// Only the file named is hashed, not the buffers or textures it refers to.
std::string sceneFingerprint(const std::string& path);

} // namespace dhdr
