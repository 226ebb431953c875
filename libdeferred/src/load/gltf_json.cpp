#include "load/gltf_json.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

namespace dhdr::detail {

std::string glbJsonChunk(const std::vector<char>& bytes) {
    if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0) return {};
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    if (std::memcmp(bytes.data() + 16, "JSON", 4) != 0 || 20 + size_t(length) > bytes.size())
        return {};
    return std::string(bytes.data() + 20, length);
}

nlohmann::json gltfJson(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return nlohmann::json(nlohmann::json::value_t::discarded);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    const std::string text = glbJsonChunk(bytes);
    return nlohmann::json::parse(text.empty() ? std::string(bytes.begin(), bytes.end()) : text,
                                 nullptr, false);
}

namespace {

// Thrown by the field readers below, caught in gltfLightsByNode.
struct FieldError {
    std::string message;
};

// A finite number that a float holds.
bool isFloat(const nlohmann::json& v) {
    return v.is_number() && std::isfinite(v.get<double>()) &&
           std::abs(v.get<double>()) <= double(std::numeric_limits<float>::max());
}

float numberOr(const nlohmann::json& j, const char* key, float fallback) {
    if (!j.contains(key)) return fallback;
    if (!isFloat(j[key])) throw FieldError{std::string("\"") + key + "\" must be a number"};
    return j[key].get<float>();
}

glm::vec3 vec3Or(const nlohmann::json& j, const char* key, glm::vec3 fallback) {
    if (!j.contains(key)) return fallback;
    const nlohmann::json& a = j[key];
    if (!a.is_array() || a.size() != 3 || !isFloat(a[0]) || !isFloat(a[1]) || !isFloat(a[2]))
        throw FieldError{std::string("\"") + key + "\" must be an array of 3 numbers"};
    return {a[0].get<float>(), a[1].get<float>(), a[2].get<float>()};
}

} // namespace

std::map<std::string, float> gltfEmissiveStrengths(const nlohmann::json& doc) {
    std::map<std::string, float> out;
    if (doc.is_discarded() || !doc.contains("materials")) return out;
    for (const auto& m : doc["materials"]) {
        if (!m.is_object() || !m.contains("name") || !m["name"].is_string()) continue;
        const auto ext = m.value("extensions", nlohmann::json::object());
        if (!ext.contains("KHR_materials_emissive_strength")) continue;
        const auto& s = ext["KHR_materials_emissive_strength"];
        if (s.contains("emissiveStrength") && isFloat(s["emissiveStrength"]))
            out[m["name"].get<std::string>()] = s["emissiveStrength"].get<float>();
    }
    return out;
}

std::map<std::string, GltfSpecular> gltfSpecular(const nlohmann::json& doc) {
    std::map<std::string, GltfSpecular> out;
    if (doc.is_discarded() || !doc.contains("materials") || !doc["materials"].is_array())
        return out;
    for (const auto& m : doc["materials"]) {
        if (!m.is_object() || !m.contains("name") || !m["name"].is_string()) continue;
        const auto ext = m.value("extensions", nlohmann::json::object());
        if (!ext.is_object() || !ext.contains("KHR_materials_specular") ||
            !ext["KHR_materials_specular"].is_object())
            continue;
        const nlohmann::json& k = ext["KHR_materials_specular"];
        GltfSpecular s;
        if (k.contains("specularFactor") && isFloat(k["specularFactor"]))
            s.factor = std::clamp(k["specularFactor"].get<float>(), 0.0f, 1.0f);
        const nlohmann::json& c = k.value("specularColorFactor", nlohmann::json());
        if (c.is_array() && c.size() == 3 && isFloat(c[0]) && isFloat(c[1]) && isFloat(c[2]))
            s.color = glm::max(glm::vec3(c[0].get<float>(), c[1].get<float>(), c[2].get<float>()),
                               glm::vec3(0.0f));
        if (k.contains("specularTexture")) s.texture = k["specularTexture"];
        if (k.contains("specularColorTexture")) s.colorTexture = k["specularColorTexture"];
        out[m["name"].get<std::string>()] = s;
    }
    return out;
}

std::map<std::string, GltfSpecGloss> gltfSpecGloss(const nlohmann::json& doc) {
    std::map<std::string, GltfSpecGloss> out;
    if (doc.is_discarded() || !doc.contains("materials") || !doc["materials"].is_array())
        return out;
    // A factor of n numbers each in [0, 1], or none when it is not that.
    auto factor = [](const nlohmann::json& k, const char* key, float* v, size_t n) {
        if (!k.contains(key)) return;
        const nlohmann::json& a = k[key];
        if (n == 1 && isFloat(a)) {
            v[0] = std::clamp(a.get<float>(), 0.0f, 1.0f);
            return;
        }
        if (!a.is_array() || a.size() != n) return;
        for (size_t i = 0; i < n; ++i)
            if (!isFloat(a[i])) return;
        for (size_t i = 0; i < n; ++i)
            v[i] = std::clamp(a[i].get<float>(), 0.0f, 1.0f);
    };
    for (const auto& m : doc["materials"]) {
        if (!m.is_object() || !m.contains("name") || !m["name"].is_string()) continue;
        const auto ext = m.value("extensions", nlohmann::json::object());
        if (!ext.is_object() || !ext.contains("KHR_materials_pbrSpecularGlossiness") ||
            !ext["KHR_materials_pbrSpecularGlossiness"].is_object())
            continue;
        const nlohmann::json& k = ext["KHR_materials_pbrSpecularGlossiness"];
        GltfSpecGloss s;
        factor(k, "diffuseFactor", &s.diffuse[0], 4);
        factor(k, "specularFactor", &s.specular[0], 3);
        factor(k, "glossinessFactor", &s.glossiness, 1);
        if (k.contains("diffuseTexture")) s.diffuseTexture = k["diffuseTexture"];
        if (k.contains("specularGlossinessTexture"))
            s.specularGlossinessTexture = k["specularGlossinessTexture"];
        out[m["name"].get<std::string>()] = s;
    }
    return out;
}

bool gltfLightsByNode(const nlohmann::json& doc, std::map<std::string, GltfLight>& out,
                      std::string& error) {
    out.clear();
    if (doc.is_discarded() || !doc.contains("nodes") || !doc["nodes"].is_array() ||
        !doc.contains("extensions") || !doc["extensions"].is_object())
        return true;
    const nlohmann::json& ext = doc["extensions"];
    if (!ext.contains("KHR_lights_punctual") || !ext["KHR_lights_punctual"].is_object())
        return true;
    const nlohmann::json& punctual = ext["KHR_lights_punctual"];
    if (!punctual.contains("lights") || !punctual["lights"].is_array()) return true;
    const nlohmann::json& lights = punctual["lights"];
    for (const auto& node : doc["nodes"]) {
        if (!node.is_object() || !node.contains("name") || !node["name"].is_string()) continue;
        if (!node.contains("extensions") || !node["extensions"].is_object()) continue;
        const nlohmann::json& nodeExt = node["extensions"];
        if (!nodeExt.contains("KHR_lights_punctual")) continue;
        const auto& ref = nodeExt["KHR_lights_punctual"];
        if (!ref.is_object() || !ref.contains("light") || !ref["light"].is_number_unsigned())
            continue;
        const size_t index = ref["light"].get<size_t>();
        if (index >= lights.size() || !lights[index].is_object()) continue;
        const auto& l = lights[index];
        GltfLight g;
        try {
            if (l.contains("type")) {
                if (!l["type"].is_string()) throw FieldError{"\"type\" must be a string"};
                g.type = l["type"].get<std::string>();
            }
            g.color = vec3Or(l, "color", glm::vec3(1.0f));
            g.intensity = numberOr(l, "intensity", 1.0f);
            g.range = numberOr(l, "range", 0.0f);
            if (l.contains("spot")) {
                if (!l["spot"].is_object()) throw FieldError{"\"spot\" must be an object"};
                g.innerConeAngle = numberOr(l["spot"], "innerConeAngle", 0.0f);
                g.outerConeAngle = numberOr(l["spot"], "outerConeAngle", 0.7853982f);
            }
        } catch (const FieldError& e) {
            error = "KHR_lights_punctual light " + std::to_string(index) + ": " + e.message;
            return false;
        }
        out[node["name"].get<std::string>()] = g;
    }
    return true;
}

std::set<std::string> gltfNames(const nlohmann::json& doc, const char* array) {
    std::set<std::string> out;
    if (doc.is_discarded() || !doc.is_object() || !doc.contains(array) || !doc[array].is_array())
        return out;
    for (const auto& e : doc[array])
        if (e.is_object() && e.contains("name") && e["name"].is_string())
            out.insert(e["name"].get<std::string>());
    return out;
}

std::map<std::string, GltfCamera> gltfCamerasByNode(const nlohmann::json& doc) {
    std::map<std::string, GltfCamera> out;
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("nodes") ||
        !doc["nodes"].is_array() || !doc.contains("cameras") || !doc["cameras"].is_array())
        return out;
    const nlohmann::json& cameras = doc["cameras"];
    for (const auto& node : doc["nodes"]) {
        if (!node.is_object() || !node.contains("name") || !node["name"].is_string() ||
            !node.contains("camera") || !node["camera"].is_number_unsigned())
            continue;
        const size_t index = node["camera"].get<size_t>();
        if (index >= cameras.size() || !cameras[index].is_object()) continue;
        const nlohmann::json& c = cameras[index];
        GltfCamera g;
        g.name = c.contains("name") && c["name"].is_string() ? c["name"].get<std::string>()
                                                             : std::to_string(index);
        // A number a float holds (Assimp reads it into one); its range is Camera::problem's to
        // judge.
        auto number = [](const nlohmann::json& j, const char* key, double fallback, bool required) {
            if (!j.contains(key)) {
                if (required) throw FieldError{std::string("has no \"") + key + "\""};
                return fallback;
            }
            if (!isFloat(j[key]))
                throw FieldError{std::string("\"") + key + "\" must be a number a float holds"};
            return j[key].get<double>();
        };
        try {
            g.orthographic = c.contains("type") && c["type"] == "orthographic";
            const char* kind = g.orthographic ? "orthographic" : "perspective";
            if (!c.contains(kind) || !c[kind].is_object())
                throw FieldError{std::string("has no \"") + kind + "\" object"};
            const nlohmann::json& p = c[kind];
            if (g.orthographic) {
                g.xmag = number(p, "xmag", 0.0, true);
                g.ymag = number(p, "ymag", 0.0, true);
                g.znear = number(p, "znear", 0.0, true);
                g.zfar = number(p, "zfar", 0.0, true);
            } else {
                g.yfov = number(p, "yfov", 0.0, true);
                g.aspectRatio = number(p, "aspectRatio", 0.0, false);
                if (p.contains("aspectRatio") && !(g.aspectRatio > 0.0))
                    throw FieldError{"its aspectRatio, " + p["aspectRatio"].dump() +
                                     ", is not a positive number"};
                g.znear = number(p, "znear", 0.0, true);
                g.zfar = number(p, "zfar", 0.0, false);
                if (p.contains("zfar") && !(g.zfar > g.znear))
                    throw FieldError{"its zfar, " + p["zfar"].dump() +
                                     ", is not greater than its znear"};
            }
        } catch (const FieldError& e) {
            g.problem = e.message;
        }
        out[node["name"].get<std::string>()] = g;
    }
    return out;
}

namespace {

// The UV set a textureInfo (or its KHR_texture_transform) names; -1 when it names none.
int texCoordOf(const nlohmann::json& info) {
    if (!info.is_object() || !info.contains("texCoord") || !info["texCoord"].is_number_integer())
        return -1;
    return info["texCoord"].get<int>();
}

// KHR_texture_transform of a textureInfo, with its texCoord override.
GltfTextureInfo textureInfo(const nlohmann::json& info) {
    GltfTextureInfo t;
    if (!info.is_object() || !info.contains("extensions") || !info["extensions"].is_object())
        return t;
    const nlohmann::json& ext = info["extensions"];
    if (!ext.contains("KHR_texture_transform") || !ext["KHR_texture_transform"].is_object())
        return t;
    const nlohmann::json& k = ext["KHR_texture_transform"];
    auto vec2 = [&](const char* key, glm::vec2 fallback) {
        if (!k.contains(key) || !k[key].is_array() || k[key].size() != 2 || !isFloat(k[key][0]) ||
            !isFloat(k[key][1]))
            return fallback;
        return glm::vec2(k[key][0].get<float>(), k[key][1].get<float>());
    };
    t.transform.offset = vec2("offset", glm::vec2(0.0f));
    t.transform.scale = vec2("scale", glm::vec2(1.0f));
    if (k.contains("rotation") && isFloat(k["rotation"]))
        t.transform.rotation = k["rotation"].get<float>();
    t.texCoord = texCoordOf(k);
    return t;
}

// A material's texture references by slot, as the file writes them (null where absent).
struct TextureSlots {
    const nlohmann::json *baseColor = nullptr, *metallicRoughness = nullptr, *normal = nullptr,
                         *occlusion = nullptr, *emissive = nullptr;
    // KHR_materials_clearcoat's.
    const nlohmann::json *clearcoat = nullptr, *clearcoatRoughness = nullptr,
                         *clearcoatNormal = nullptr;
    // KHR_materials_sheen's.
    const nlohmann::json *sheenColor = nullptr, *sheenRoughness = nullptr;
    // KHR_materials_specular's.
    const nlohmann::json *specular = nullptr, *specularColor = nullptr;
    // KHR_materials_pbrSpecularGlossiness's.
    const nlohmann::json *diffuse = nullptr, *specularGlossiness = nullptr;

    // KHR_materials_transmission's.
    const nlohmann::json* transmission = nullptr;

    // Each of them, for what applies to every slot.
    std::vector<const nlohmann::json*> all() const {
        return {baseColor, metallicRoughness,  normal,          occlusion,          emissive,
                clearcoat, clearcoatRoughness, clearcoatNormal, sheenColor,         sheenRoughness,
                specular,  specularColor,      diffuse,         specularGlossiness, transmission};
    }
};

TextureSlots textureSlots(const nlohmann::json& m) {
    TextureSlots t;
    if (!m.is_object()) return t;
    auto at = [](const nlohmann::json& o, const char* key) {
        return o.contains(key) ? &o[key] : nullptr;
    };
    if (m.contains("pbrMetallicRoughness") && m["pbrMetallicRoughness"].is_object()) {
        t.baseColor = at(m["pbrMetallicRoughness"], "baseColorTexture");
        t.metallicRoughness = at(m["pbrMetallicRoughness"], "metallicRoughnessTexture");
    }
    t.normal = at(m, "normalTexture");
    t.occlusion = at(m, "occlusionTexture");
    t.emissive = at(m, "emissiveTexture");
    if (m.contains("extensions") && m["extensions"].is_object() &&
        m["extensions"].contains("KHR_materials_clearcoat") &&
        m["extensions"]["KHR_materials_clearcoat"].is_object()) {
        const nlohmann::json& c = m["extensions"]["KHR_materials_clearcoat"];
        t.clearcoat = at(c, "clearcoatTexture");
        t.clearcoatRoughness = at(c, "clearcoatRoughnessTexture");
        t.clearcoatNormal = at(c, "clearcoatNormalTexture");
    }
    if (m.contains("extensions") && m["extensions"].is_object() &&
        m["extensions"].contains("KHR_materials_sheen") &&
        m["extensions"]["KHR_materials_sheen"].is_object()) {
        const nlohmann::json& c = m["extensions"]["KHR_materials_sheen"];
        t.sheenColor = at(c, "sheenColorTexture");
        t.sheenRoughness = at(c, "sheenRoughnessTexture");
    }
    auto extension = [&](const char* name) -> const nlohmann::json* {
        if (!m.contains("extensions") || !m["extensions"].is_object() ||
            !m["extensions"].contains(name) || !m["extensions"][name].is_object())
            return nullptr;
        return &m["extensions"][name];
    };
    if (const nlohmann::json* c = extension("KHR_materials_specular")) {
        t.specular = at(*c, "specularTexture");
        t.specularColor = at(*c, "specularColorTexture");
    }
    if (const nlohmann::json* c = extension("KHR_materials_pbrSpecularGlossiness")) {
        t.diffuse = at(*c, "diffuseTexture");
        t.specularGlossiness = at(*c, "specularGlossinessTexture");
    }
    if (const nlohmann::json* c = extension("KHR_materials_transmission"))
        t.transmission = at(*c, "transmissionTexture");
    return t;
}

} // namespace

std::map<std::string, GltfMaterialTextures> gltfMaterialTextures(const nlohmann::json& doc) {
    std::map<std::string, GltfMaterialTextures> out;
    if (doc.is_discarded() || !doc.contains("materials") || !doc["materials"].is_array())
        return out;
    for (const auto& m : doc["materials"]) {
        if (!m.is_object() || !m.contains("name") || !m["name"].is_string()) continue;
        const TextureSlots slots = textureSlots(m);
        auto info = [](const nlohmann::json* ref) {
            return ref ? textureInfo(*ref) : GltfTextureInfo{};
        };
        out[m["name"].get<std::string>()] = {info(slots.baseColor),
                                             info(slots.emissive),
                                             info(slots.normal),
                                             info(slots.metallicRoughness),
                                             info(slots.occlusion),
                                             info(slots.clearcoat),
                                             info(slots.clearcoatRoughness),
                                             info(slots.clearcoatNormal),
                                             info(slots.sheenColor),
                                             info(slots.sheenRoughness),
                                             info(slots.specular),
                                             info(slots.specularColor),
                                             info(slots.diffuse),
                                             info(slots.specularGlossiness),
                                             info(slots.transmission)};
    }
    return out;
}

bool gltfHasRgbVertexColors(const nlohmann::json& doc) {
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("meshes") ||
        !doc["meshes"].is_array() || !doc.contains("accessors") || !doc["accessors"].is_array())
        return false;
    const nlohmann::json& accessors = doc["accessors"];
    for (const auto& mesh : doc["meshes"]) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
            continue;
        for (const auto& p : mesh["primitives"]) {
            if (!p.is_object() || !p.contains("attributes") || !p["attributes"].is_object() ||
                !p["attributes"].contains("COLOR_0") ||
                !p["attributes"]["COLOR_0"].is_number_unsigned())
                continue;
            const size_t i = p["attributes"]["COLOR_0"].get<size_t>();
            if (i < accessors.size() && accessors[i].is_object() && accessors[i].contains("type") &&
                accessors[i]["type"] == "VEC3")
                return true;
        }
    }
    return false;
}

std::string gltfEmptySceneReason(const nlohmann::json& doc) {
    if (doc.is_discarded() || !doc.is_object()) return {};
    if (!doc.contains("scenes") || !doc["scenes"].is_array() || doc["scenes"].empty())
        return "the file has no scene";
    const size_t index =
        doc.contains("scene") && doc["scene"].is_number_unsigned() ? doc["scene"].get<size_t>() : 0;
    if (index >= doc["scenes"].size()) return "its default scene does not exist";
    const nlohmann::json& scene = doc["scenes"][index];
    if (!scene.is_object() || !scene.contains("nodes") || !scene["nodes"].is_array() ||
        scene["nodes"].empty())
        return "its scene has no nodes (nothing to render)";
    return {};
}

namespace {

// glTF 1.0 files give their version as "1.0" or as the number 1.
bool isGltf1(const nlohmann::json& doc) {
    if (!doc.is_object() || !doc.contains("asset") || !doc["asset"].is_object() ||
        !doc["asset"].contains("version"))
        return false;
    const nlohmann::json& v = doc["asset"]["version"];
    return (v.is_number() && v.get<double>() < 2.0) ||
           (v.is_string() && v.get<std::string>().rfind('1', 0) == 0);
}

} // namespace

bool gltfExtensionRendered(const nlohmann::json& doc, const std::string& name) {
    // Assimp 5.2 decodes Draco meshes (Debian's is built with libdraco); dhdr reads the others
    // itself or through Assimp.
    static const char* const kGltf2[] = {"KHR_draco_mesh_compression",
                                         "KHR_lights_punctual",
                                         "KHR_materials_emissive_strength",
                                         "KHR_texture_transform",
                                         "KHR_materials_ior",
                                         "KHR_materials_specular",
                                         "KHR_materials_unlit",
                                         "KHR_materials_clearcoat",
                                         "KHR_materials_sheen",
                                         "KHR_materials_transmission",
                                         "KHR_materials_volume",
                                         "KHR_materials_pbrSpecularGlossiness"};
    // Assimp's glTF 1.0 importer reads the binary container and the common materials' colours.
    static const char* const kGltf1[] = {"KHR_binary_glTF", "KHR_materials_common"};
    auto among = [&](const auto& list) {
        return std::find(std::begin(list), std::end(list), name) != std::end(list);
    };
    return isGltf1(doc) ? among(kGltf1) : among(kGltf2);
}

std::map<std::string, std::vector<std::string>> gltfMaterialExtensions(const nlohmann::json& doc) {
    std::map<std::string, std::vector<std::string>> out;
    if (doc.is_discarded() || !doc.contains("materials") || !doc["materials"].is_array())
        return out;
    for (const auto& m : doc["materials"]) {
        if (!m.is_object() || !m.contains("name") || !m["name"].is_string() ||
            m["name"].get<std::string>().empty() || !m.contains("extensions") ||
            !m["extensions"].is_object())
            continue;
        std::vector<std::string> names;
        for (const auto& e : m["extensions"].items())
            names.push_back(e.key());
        out[m["name"].get<std::string>()] = names;
    }
    return out;
}

std::string gltfDracoIndexProblem(const nlohmann::json& doc) {
    if (doc.is_discarded() || !doc.contains("meshes") || !doc["meshes"].is_array() ||
        !doc.contains("accessors") || !doc["accessors"].is_array())
        return {};
    const nlohmann::json& accessors = doc["accessors"];
    for (size_t i = 0; i < doc["meshes"].size(); ++i) {
        const nlohmann::json& mesh = doc["meshes"][i];
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
            continue;
        for (const auto& p : mesh["primitives"]) {
            if (!p.is_object() || !p.contains("extensions") || !p["extensions"].is_object() ||
                !p["extensions"].contains("KHR_draco_mesh_compression") || !p.contains("indices") ||
                !p["indices"].is_number_unsigned())
                continue;
            const size_t a = p["indices"].get<size_t>();
            // An accessor with its own data (an uncompressed fallback) is read from it.
            if (a >= accessors.size() || !accessors[a].is_object() ||
                accessors[a].contains("bufferView") ||
                accessors[a].value("componentType", nlohmann::json()) != 5125)
                continue;
            const bool named = mesh.contains("name") && mesh["name"].is_string();
            return "mesh " +
                   (named ? "'" + mesh["name"].get<std::string>() + "'" : std::to_string(i)) +
                   " is Draco-compressed with 32-bit indices, which Assimp 5.2 loses (it reads "
                   "8- and 16-bit ones)";
        }
    }
    return {};
}

size_t gltfUnplayedAnimations(const nlohmann::json& doc) {
    if (doc.is_discarded() || !isGltf1(doc) || !doc.contains("animations")) return 0;
    const nlohmann::json& a = doc["animations"];
    return a.is_object() || a.is_array() ? a.size() : 0;
}

std::vector<std::string> gltfIgnoredFeatures(const nlohmann::json& doc) {
    std::vector<std::string> out;
    if (doc.is_discarded() || !doc.is_object()) return out;
    if (doc.contains("extensionsUsed") && doc["extensionsUsed"].is_array()) {
        std::string ignored;
        for (const auto& e : doc["extensionsUsed"]) {
            if (!e.is_string()) continue;
            const std::string name = e.get<std::string>();
            if (!gltfExtensionRendered(doc, name)) ignored += (ignored.empty() ? "" : ", ") + name;
        }
        if (!ignored.empty()) out.push_back("glTF extensions not read: " + ignored);
    }
    bool morph = false;
    if (doc.contains("meshes") && doc["meshes"].is_array())
        for (const auto& mesh : doc["meshes"])
            if (mesh.is_object() && mesh.contains("primitives") && mesh["primitives"].is_array())
                for (const auto& p : mesh["primitives"])
                    morph = morph || (p.is_object() && p.contains("targets"));
    // A file with animations has its morph targets and skins applied (gltf_morph.h).
    const bool animated =
        doc.contains("animations") && doc["animations"].is_array() && !doc["animations"].empty();
    morph = morph && !animated;
    const bool skins =
        !animated && doc.contains("skins") && doc["skins"].is_array() && !doc["skins"].empty();
    if (skins || morph)
        out.push_back(std::string(skins && morph ? "skins and morph targets"
                                  : skins        ? "skins"
                                                 : "morph targets") +
                      " are not applied: meshes are rendered in their rest pose");
    // TEXCOORD_0 and _1 are read; a texture on a later set falls back to the first.
    std::string pastSecondSet; // the materials that name one
    if (doc.contains("materials") && doc["materials"].is_array())
        for (size_t i = 0; i < doc["materials"].size(); ++i) {
            const nlohmann::json& m = doc["materials"][i];
            int highestSet = 0;
            for (const nlohmann::json* ref : textureSlots(m).all())
                if (ref)
                    highestSet =
                        std::max({highestSet, texCoordOf(*ref), textureInfo(*ref).texCoord});
            if (highestSet <= 1) continue;
            const bool named = m.contains("name") && m["name"].is_string();
            pastSecondSet += (pastSecondSet.empty() ? "" : ", ") +
                             (named ? "'" + m["name"].get<std::string>() + "'"
                                    : "materials[" + std::to_string(i) + "]");
        }
    if (!pastSecondSet.empty())
        out.push_back("textures on UV sets past TEXCOORD_1 are sampled with TEXCOORD_0 (material " +
                      pastSecondSet + ")");
    return out;
}

} // namespace dhdr::detail
