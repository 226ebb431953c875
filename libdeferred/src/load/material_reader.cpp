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

// The base colour, emissive and normal textures, with their KHR_texture_transform.
void readTextures(const aiMaterial& am, const GltfMaterialTextures& transforms,
                  TextureTable& textures, Material& m) {
    aiString texPath;
    if (am.GetTexture(aiTextureType_BASE_COLOR, 0, &texPath) == AI_SUCCESS ||
        am.GetTexture(aiTextureType_DIFFUSE, 0, &texPath) == AI_SUCCESS) {
        m.baseColorTexture.texture = textures.load(texPath.C_Str(), true, "base colour");
        m.baseColorTexture.transform = transforms.baseColor;
    }
    if (am.GetTexture(aiTextureType_EMISSIVE, 0, &texPath) == AI_SUCCESS) {
        m.emissiveTexture.texture = textures.load(texPath.C_Str(), true, "emissive");
        m.emissiveTexture.transform = transforms.emissive;
    }
    if (am.GetTexture(aiTextureType_NORMALS, 0, &texPath) == AI_SUCCESS) {
        m.normalTexture.texture = textures.load(texPath.C_Str(), false, "normal");
        m.normalTexture.transform = transforms.normal;
        m.normalScale = transforms.normalScale;
    }
}

} // namespace

void readMaterials(const aiScene& ai, const nlohmann::json& doc, bool gltf, TextureTable& textures,
                   Scene& scene) {
    const auto strengths = gltf ? gltfEmissiveStrengths(doc) : std::map<std::string, float>{};
    const auto transforms =
        gltf ? gltfMaterialTextures(doc) : std::map<std::string, GltfMaterialTextures>{};
    for (unsigned i = 0; i < ai.mNumMaterials; ++i) {
        const aiMaterial& am = *ai.mMaterials[i];
        Material m;
        m.name = am.GetName().C_Str();
        readBaseAndAlpha(am, gltf, m);
        readMetallicRoughness(am, gltf, m);
        readEmission(am, strengths, m);
        const auto t = transforms.find(m.name);
        readTextures(am, t != transforms.end() ? t->second : GltfMaterialTextures{}, textures, m);
        scene.materials.push_back(m);
    }
    if (scene.materials.empty()) scene.materials.push_back(Material{});
}

} // namespace dhdr::detail
