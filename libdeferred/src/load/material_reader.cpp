#include "load/material_reader.h"

#include "load/gltf_json.h"

#include <algorithm>
#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/scene.h>
#include <cmath>
#include <map>

namespace dhdr::detail {

namespace {

// The base colour and the alpha mode: glTF's, or for OBJ/MTL the opacity.
void readBaseAndAlpha(const aiMaterial& am, bool gltf, Material& m) {
    aiColor4D base;
    if (am.Get(AI_MATKEY_BASE_COLOR, base) == AI_SUCCESS ||
        am.Get(AI_MATKEY_COLOR_DIFFUSE, base) == AI_SUCCESS) {
        m.baseColor = glm::vec3(base.r, base.g, base.b);
        m.alpha = base.a;
    }
    if (gltf) {
        aiString mode;
        if (am.Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS) {
            const std::string name = mode.C_Str();
            m.alphaMode = name == "BLEND"  ? AlphaMode::Blend
                          : name == "MASK" ? AlphaMode::Mask
                                           : AlphaMode::Opaque;
        }
        float cutoff = 0.5f;
        if (am.Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff) == AI_SUCCESS) m.alphaCutoff = cutoff;
    } else {
        // OBJ/MTL: Assimp reports d (or 1 − Tr) as the opacity; below 1 it blends.
        float opacity = 1.0f;
        if (am.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && opacity < 1.0f) {
            m.alpha = std::clamp(opacity, 0.0f, 1.0f);
            m.alphaMode = AlphaMode::Blend;
        }
    }
}

void readMetallicRoughness(const aiMaterial& am, bool gltf, Material& m) {
    float metallic = 0.0f, roughness = 1.0f;
    // glTF's factors, or the MTL's PBR extension (Pm, Pr) that Assimp reports the same.
    if (am.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == AI_SUCCESS) {
        m.metallic = metallic;
        float shininess = 0.0f;
        if (am.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness) == AI_SUCCESS)
            m.roughness = roughness;
        else if (!gltf && am.Get(AI_MATKEY_SHININESS, shininess) == AI_SUCCESS)
            m.roughness = std::sqrt(std::sqrt(2.0f / (shininess + 2.0f)));
    } else {
        // Not a PBR material (OBJ/MTL): a dielectric, roughness from the Phong
        // exponent by the usual α = sqrt(2 / (Ns + 2)) match.
        m.metallic = 0.0f;
        float shininess = 0.0f;
        m.roughness = am.Get(AI_MATKEY_SHININESS, shininess) == AI_SUCCESS
                          ? std::sqrt(std::sqrt(2.0f / (shininess + 2.0f)))
                          : 1.0f;
    }
}

// `strengths`: KHR_materials_emissive_strength by material name, from the file.
void readEmission(const aiMaterial& am, const std::map<std::string, float>& strengths,
                  Material& m) {
    aiColor3D emissive(0.0f, 0.0f, 0.0f);
    am.Get(AI_MATKEY_COLOR_EMISSIVE, emissive);
    float strength = 1.0f;
    // Assimp 5.2 drops KHR_materials_emissive_strength; newer ones report it here.
    if (am.Get(AI_MATKEY_EMISSIVE_INTENSITY, strength) != AI_SUCCESS) {
        const auto it = strengths.find(m.name);
        strength = it != strengths.end() ? it->second : 1.0f;
    }
    m.emission = glm::vec3(emissive.r, emissive.g, emissive.b) * strength;
}

TextureWrap wrapOf(aiTextureMapMode mode) {
    switch (mode) {
    case aiTextureMapMode_Clamp:
        return TextureWrap::ClampToEdge;
    case aiTextureMapMode_Mirror:
        return TextureWrap::MirroredRepeat;
    default:
        return TextureWrap::Repeat;
    }
}

// The texture of slot `type` into `ref`: its file, UV set and sampler as Assimp 5.2 reports
// them for glTF (AI_MATKEY_UVWSRC, AI_MATKEY_MAPPINGMODE_U/V, the glTF mag filter), the
// KHR_texture_transform and its texCoord override from the file (`info`). False when the
// material has none.
bool readSlot(const aiMaterial& am, aiTextureType type, const GltfTextureInfo& info, bool srgb,
              const char* slot, TextureTable& textures, TextureRef& ref, unsigned index = 0) {
    aiString path;
    unsigned uvIndex = 0;
    aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
    if (am.GetTexture(type, index, &path, nullptr, &uvIndex, nullptr, nullptr, modes) != AI_SUCCESS)
        return false;
    ref.texture = textures.load(path.C_Str(), srgb, slot);
    ref.transform = info.transform;
    // TEXCOORD_0 and _1 are kept; a later set falls back to the first (gltfIgnoredFeatures).
    const int set = info.texCoord >= 0 ? info.texCoord : int(uvIndex);
    ref.texCoord = set == 1 ? 1 : 0;
    ref.sampler.wrapS = wrapOf(modes[0]);
    ref.sampler.wrapT = wrapOf(modes[1]);
    int magFilter = 0;
    constexpr int kNearest = 9728; // glTF's (and OpenGL's) NEAREST
    ref.sampler.nearest =
        am.Get(AI_MATKEY_GLTF_MAPPINGFILTER_MAG(type, index), magFilter) == AI_SUCCESS &&
        magFilter == kNearest;
    return true;
}

// A texture reference that Assimp 5.2 does not report (KHR_materials_specular's; and
// KHR_materials_pbrSpecularGlossiness's unless extensionsUsed names it), read from the file's
// JSON as readSlot reads Assimp's: the textureInfo `json` (its index into the file's
// textures, that texture's image and sampler, its texCoord) with its KHR_texture_transform
// (`info`). A reference that leads to no image is an unread texture (TextureTable::report warns,
// naming the material). False when `json` is absent.
bool readJsonSlot(const nlohmann::json& doc, const nlohmann::json& json,
                  const GltfTextureInfo& info, bool srgb, const char* slot, TextureTable& textures,
                  TextureRef& ref) {
    if (json.is_null()) return false;
    const nlohmann::json* list = doc.contains("textures") ? &doc["textures"] : nullptr;
    const nlohmann::json* texture = nullptr;
    if (!json.is_object() || !json.contains("index") || !json["index"].is_number_unsigned()) {
        ref.texture = textures.unreadable(
            "its textureInfo " + json.dump().substr(0, 60) + " has no index", slot);
    } else if (const size_t index = json["index"].get<size_t>();
               !list || !list->is_array() || index >= list->size() || !(*list)[index].is_object()) {
        ref.texture =
            textures.unreadable("texture " + std::to_string(index) + " does not exist", slot);
    } else if (texture = &(*list)[index];
               !texture->contains("source") || !(*texture)["source"].is_number_unsigned()) {
        ref.texture = textures.unreadable(
            "texture " + std::to_string(index) + " names no image (no \"source\")", slot);
    } else {
        ref.texture = textures.loadGltfImage(doc, (*texture)["source"].get<size_t>(), srgb, slot);
    }
    ref.transform = info.transform;
    // TEXCOORD_0 and _1 are kept; a later set falls back to the first (gltfIgnoredFeatures).
    const bool second =
        info.texCoord >= 0 ? info.texCoord == 1
                           : json.is_object() && json.contains("texCoord") && json["texCoord"] == 1;
    ref.texCoord = second ? 1 : 0;
    // The sampler (glTF 2.0 §5.26): wrap modes as Assimp 5.2 maps them (an unknown one is
    // REPEAT), the mag filter NEAREST or not.
    const nlohmann::json* samplers = doc.contains("samplers") ? &doc["samplers"] : nullptr;
    if (texture && texture->contains("sampler") && (*texture)["sampler"].is_number_unsigned() &&
        samplers && samplers->is_array() &&
        (*texture)["sampler"].get<size_t>() < samplers->size()) {
        const nlohmann::json& sampler = (*samplers)[(*texture)["sampler"].get<size_t>()];
        auto mode = [&](const char* key) {
            return sampler.is_object() && sampler.contains(key) ? sampler[key]
                                                                : nlohmann::json(nullptr);
        };
        auto wrap = [&](const char* key) {
            return mode(key) == 33071   ? TextureWrap::ClampToEdge
                   : mode(key) == 33648 ? TextureWrap::MirroredRepeat
                                        : TextureWrap::Repeat;
        };
        ref.sampler.wrapS = wrap("wrapS");
        ref.sampler.wrapT = wrap("wrapT");
        constexpr int kNearest = 9728; // glTF's (and OpenGL's) NEAREST
        ref.sampler.nearest = mode("magFilter") == kNearest;
    }
    return true;
}

// Every texture slot of the material (glTF 2.0 §3.9), with the file's texture-transform data.
void readTextures(const aiMaterial& am, bool gltf, const GltfMaterialTextures& info,
                  TextureTable& textures, Material& m) {
    if (!readSlot(am, aiTextureType_BASE_COLOR, info.baseColor, true, "base colour", textures,
                  m.baseColorTexture))
        readSlot(am, aiTextureType_DIFFUSE, info.baseColor, true, "base colour", textures,
                 m.baseColorTexture);
    readSlot(am, aiTextureType_EMISSIVE, info.emissive, true, "emissive", textures,
             m.emissiveTexture);
    if (readSlot(am, aiTextureType_NORMALS, info.normal, false, "normal", textures,
                 m.normalTexture))
        am.Get(AI_MATKEY_GLTF_TEXTURE_SCALE(aiTextureType_NORMALS, 0), m.normalScale);
    if (!std::isfinite(m.normalScale)) m.normalScale = 1.0f; // a number past float's range
    if (!gltf) return; // MTL's map_Pr, map_Pm are one texture each, not glTF's packed one
    readSlot(am, aiTextureType_METALNESS, info.metallicRoughness, false, "metallic-roughness",
             textures, m.metallicRoughnessTexture);
    if (readSlot(am, aiTextureType_LIGHTMAP, info.occlusion, false, "occlusion", textures,
                 m.occlusionTexture))
        am.Get(AI_MATKEY_GLTF_TEXTURE_STRENGTH(aiTextureType_LIGHTMAP, 0), m.occlusionStrength);
    // The schema's range, [0, 1].
    m.occlusionStrength =
        std::isfinite(m.occlusionStrength) ? std::clamp(m.occlusionStrength, 0.0f, 1.0f) : 1.0f;
}

// KHR_materials_clearcoat, as Assimp 5.2 reads it: the factors (clamped to the schema's
// [0, 1]) and the three textures of aiTextureType_CLEARCOAT.
void readClearcoat(const aiMaterial& am, const GltfMaterialTextures& info, TextureTable& textures,
                   Material& m) {
    float factor = 0.0f, roughness = 0.0f;
    if (am.Get(AI_MATKEY_CLEARCOAT_FACTOR, factor) != AI_SUCCESS || !(factor > 0.0f)) return;
    am.Get(AI_MATKEY_CLEARCOAT_ROUGHNESS_FACTOR, roughness);
    m.clearcoat = std::min(factor, 1.0f);
    m.clearcoatRoughness = std::isfinite(roughness) ? std::clamp(roughness, 0.0f, 1.0f) : 0.0f;
    readSlot(am, aiTextureType_CLEARCOAT, info.clearcoat, false, "clearcoat", textures,
             m.clearcoatTexture, 0);
    readSlot(am, aiTextureType_CLEARCOAT, info.clearcoatRoughness, false, "clearcoat roughness",
             textures, m.clearcoatRoughnessTexture, 1);
    if (readSlot(am, aiTextureType_CLEARCOAT, info.clearcoatNormal, false, "clearcoat normal",
                 textures, m.clearcoatNormalTexture, 2))
        am.Get(AI_MATKEY_GLTF_TEXTURE_SCALE(aiTextureType_CLEARCOAT, 2), m.clearcoatNormalScale);
    if (!std::isfinite(m.clearcoatNormalScale)) m.clearcoatNormalScale = 1.0f;
}

// KHR_materials_sheen, as Assimp 5.2 reads it: the colour and roughness factors (clamped to the
// schema's [0, 1]) and the two textures of aiTextureType_SHEEN (colour sRGB, roughness in A).
void readSheen(const aiMaterial& am, const GltfMaterialTextures& info, TextureTable& textures,
               Material& m) {
    aiColor3D color(0.0f, 0.0f, 0.0f);
    if (am.Get(AI_MATKEY_SHEEN_COLOR_FACTOR, color) != AI_SUCCESS) return;
    float roughness = 0.0f;
    am.Get(AI_MATKEY_SHEEN_ROUGHNESS_FACTOR, roughness);
    auto unit = [](float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; };
    m.sheenColor = glm::vec3(unit(color.r), unit(color.g), unit(color.b));
    m.sheenRoughness = unit(roughness);
    if (!m.sheen()) return; // a black sheen is none
    readSlot(am, aiTextureType_SHEEN, info.sheenColor, true, "sheen colour", textures,
             m.sheenColorTexture, 0);
    readSlot(am, aiTextureType_SHEEN, info.sheenRoughness, false, "sheen roughness", textures,
             m.sheenRoughnessTexture, 1);
}

// KHR_materials_transmission, as Assimp 5.2 reads it: the factor (clamped to the schema's
// [0, 1]) and its texture (the first of aiTextureType_TRANSMISSION, R linear).
void readTransmission(const aiMaterial& am, const GltfMaterialTextures& info,
                      TextureTable& textures, Material& m) {
    float factor = 0.0f;
    if (am.Get(AI_MATKEY_TRANSMISSION_FACTOR, factor) != AI_SUCCESS) return;
    m.transmission = std::isfinite(factor) ? std::clamp(factor, 0.0f, 1.0f) : 0.0f;
    if (m.transmission <= 0.0f) return;
    readSlot(am, aiTextureType_TRANSMISSION, info.transmission, false, "transmission", textures,
             m.transmissionTexture, 0);
}

// KHR_materials_volume, as Assimp 5.2 reads it: the thickness factor (0: thin walled), the
// attenuation distance (> 0; absent: infinite) and colour (each in [0, 1]). The thickness
// texture is not needed: the distance light travels inside is measured along each ray.
void readVolume(const aiMaterial& am, Material& m) {
    float thickness = 0.0f, distance = INFINITY;
    aiColor3D color(1.0f, 1.0f, 1.0f);
    if (am.Get(AI_MATKEY_VOLUME_THICKNESS_FACTOR, thickness) != AI_SUCCESS) return;
    m.thickness = std::isfinite(thickness) ? std::max(thickness, 0.0f) : 0.0f;
    if (am.Get(AI_MATKEY_VOLUME_ATTENUATION_DISTANCE, distance) == AI_SUCCESS)
        m.attenuationDistance = distance > 0.0f ? distance : INFINITY; // NaN too
    if (am.Get(AI_MATKEY_VOLUME_ATTENUATION_COLOR, color) == AI_SUCCESS) {
        auto unit = [](float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 1.0f; };
        m.attenuationColor = glm::vec3(unit(color.r), unit(color.g), unit(color.b));
    }
}

// glTF's dielectric layer: KHR_materials_ior (Assimp 5.2 reports it as AI_MATKEY_REFRACTI),
// KHR_materials_specular (from the file, `specular`, its textures resolved from the file's JSON
// `doc`), and KHR_materials_unlit (Assimp's unlit shading model).
void readDielectric(const aiMaterial& am, const nlohmann::json& doc,
                    const std::map<std::string, GltfSpecular>& specular,
                    const GltfMaterialTextures& info, TextureTable& textures, Material& m) {
    float ior = 1.5f;
    if (am.Get(AI_MATKEY_REFRACTI, ior) == AI_SUCCESS) {
        // The schema's range: 1 or more (0, "infinitely refractive", is not a dielectric).
        m.ior = std::isfinite(ior) ? std::max(ior, 1.0f) : 1.5f;
        m.dielectricSet = true;
    }
    int shading = 0;
    if (am.Get(AI_MATKEY_SHADING_MODEL, shading) == AI_SUCCESS && shading == aiShadingMode_Unlit)
        m.unlit = m.dielectricSet = true;
    const auto it = specular.find(m.name);
    if (it == specular.end()) return;
    m.specularFactor = it->second.factor;
    m.specularColor = it->second.color;
    m.dielectricSet = true;
    // specularTexture's A is linear, specularColorTexture's RGB sRGB-encoded (the README's
    // table): the data texture's alpha and the colour texture's decoded RGB.
    readJsonSlot(doc, it->second.texture, info.specular, false, "specular", textures,
                 m.specularTexture);
    readJsonSlot(doc, it->second.colorTexture, info.specularColor, true, "specular colour",
                 textures, m.specularColorTexture);
}

// KHR_materials_pbrSpecularGlossiness as the metal-rough model with KHR_materials_specular's
// dielectric that the extension's own BRDF is (specGlossAsMetalRough): metallic 0, F90 1, and
// the diffuse texture (or none: the metal-rough fallback texture is not the material's) in the
// base colour's place. Its specularGlossinessTexture (RGB sRGB, A linear: one sRGB texture, whose
// alpha stays linear) makes the conversion one per texel (surface.cpp).
void readSpecGloss(const nlohmann::json& doc, const std::map<std::string, GltfSpecGloss>& specGloss,
                   const GltfMaterialTextures& info, TextureTable& textures, Material& m) {
    const auto it = specGloss.find(m.name);
    if (it == specGloss.end()) return;
    const GltfSpecGloss& sg = it->second;
    const MetalRoughFromSpecGloss c =
        specGlossAsMetalRough(glm::vec3(sg.diffuse), sg.specular, sg.glossiness);
    m.baseColor = c.baseColor;
    m.alpha = sg.diffuse.a;
    m.metallic = 0.0f;
    m.roughness = c.roughness;
    m.metallicRoughnessTexture = TextureRef{};
    // F0 = min(((ior − 1) / (ior + 1))² · specularColor, 1) · specularFactor with ior 1.5.
    m.ior = 1.5f;
    m.specularFactor = 1.0f;
    m.specularColor = c.f0 / 0.04f;
    m.dielectricSet = true;
    m.baseColorTexture = TextureRef{};
    // From the file's JSON, as KHR_materials_specular's: Assimp 5.2 reports them only when
    // extensionsUsed names the extension (and then the diffuse texture in the DIFFUSE slot,
    // over the fallback's), where dhdr reads the factors regardless.
    readJsonSlot(doc, sg.diffuseTexture, info.diffuse, true, "diffuse", textures,
                 m.baseColorTexture);
    if (readJsonSlot(doc, sg.specularGlossinessTexture, info.specularGlossiness, true,
                     "specular-glossiness", textures, m.specularGlossinessTexture)) {
        m.baseColor = glm::vec3(sg.diffuse);
        m.glossSpecular = sg.specular;
        m.glossiness = sg.glossiness;
    }
}

} // namespace

void readMaterials(const aiScene& ai, const nlohmann::json& doc, bool gltf, TextureTable& textures,
                   Scene& scene) {
    const auto strengths = gltf ? gltfEmissiveStrengths(doc) : std::map<std::string, float>{};
    const auto transforms =
        gltf ? gltfMaterialTextures(doc) : std::map<std::string, GltfMaterialTextures>{};
    const auto specular = gltf ? gltfSpecular(doc) : std::map<std::string, GltfSpecular>{};
    const auto specGloss = gltf ? gltfSpecGloss(doc) : std::map<std::string, GltfSpecGloss>{};
    for (unsigned i = 0; i < ai.mNumMaterials; ++i) {
        const aiMaterial& am = *ai.mMaterials[i];
        Material m;
        m.name = am.GetName().C_Str();
        readBaseAndAlpha(am, gltf, m);
        readMetallicRoughness(am, gltf, m);
        readEmission(am, strengths, m);
        const auto t = transforms.find(m.name);
        const GltfMaterialTextures info =
            t != transforms.end() ? t->second : GltfMaterialTextures{};
        readTextures(am, gltf, info, textures, m);
        if (gltf) {
            readClearcoat(am, info, textures, m);
            readSheen(am, info, textures, m);
            readTransmission(am, info, textures, m);
            readVolume(am, m);
            readDielectric(am, doc, specular, info, textures, m);
            readSpecGloss(doc, specGloss, info, textures, m);
        }
        scene.materials.push_back(m);
    }
    if (scene.materials.empty()) scene.materials.push_back(Material{});
}

} // namespace dhdr::detail
