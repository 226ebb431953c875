#include "gltf_json.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <vector>

namespace dhdr::detail {

namespace {

// The JSON chunk of a binary glTF: 12-byte header, then chunk length, chunk type "JSON".
std::string glbJsonChunk(const std::vector<char>& bytes) {
    if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0) return {};
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    if (std::memcmp(bytes.data() + 16, "JSON", 4) != 0 || 20 + size_t(length) > bytes.size())
        return {};
    return std::string(bytes.data() + 20, length);
}

// The JSON document of a .gltf or .glb file; discarded when it is neither.
nlohmann::json readGltfJson(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return nlohmann::json(nlohmann::json::value_t::discarded);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    const std::string text = glbJsonChunk(bytes);
    return nlohmann::json::parse(text.empty() ? std::string(bytes.begin(), bytes.end()) : text,
                                 nullptr, false);
}

glm::vec3 vec3Or(const nlohmann::json& j, const char* key, glm::vec3 fallback) {
    if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3) return fallback;
    glm::vec3 v;
    for (int i = 0; i < 3; ++i) {
        if (!j[key][size_t(i)].is_number()) return fallback;
        v[i] = j[key][size_t(i)].get<float>();
    }
    return v;
}

} // namespace

std::map<std::string, float> gltfEmissiveStrengths(const std::string& path) {
    std::map<std::string, float> out;
    const nlohmann::json doc = readGltfJson(path);
    if (doc.is_discarded() || !doc.contains("materials")) return out;
    for (const auto& m : doc["materials"]) {
        if (!m.is_object() || !m.contains("name") || !m["name"].is_string()) continue;
        const auto ext = m.value("extensions", nlohmann::json::object());
        if (!ext.contains("KHR_materials_emissive_strength")) continue;
        const auto& s = ext["KHR_materials_emissive_strength"];
        if (s.contains("emissiveStrength") && s["emissiveStrength"].is_number())
            out[m["name"].get<std::string>()] = s["emissiveStrength"].get<float>();
    }
    return out;
}

std::map<std::string, GltfLight> gltfLightsByNode(const std::string& path) {
    std::map<std::string, GltfLight> out;
    const nlohmann::json doc = readGltfJson(path);
    if (doc.is_discarded() || !doc.contains("nodes")) return out;
    const auto ext = doc.value("extensions", nlohmann::json::object());
    if (!ext.contains("KHR_lights_punctual")) return out;
    const auto lights = ext["KHR_lights_punctual"].value("lights", nlohmann::json::array());
    for (const auto& node : doc["nodes"]) {
        if (!node.is_object() || !node.contains("name") || !node["name"].is_string()) continue;
        const auto nodeExt = node.value("extensions", nlohmann::json::object());
        if (!nodeExt.contains("KHR_lights_punctual")) continue;
        const auto& ref = nodeExt["KHR_lights_punctual"];
        if (!ref.contains("light") || !ref["light"].is_number_integer()) continue;
        const size_t index = ref["light"].get<size_t>();
        if (index >= lights.size() || !lights[index].is_object()) continue;
        const auto& l = lights[index];
        GltfLight g;
        g.type = l.value("type", std::string("point"));
        g.color = vec3Or(l, "color", glm::vec3(1.0f));
        g.intensity = l.value("intensity", 1.0f);
        g.range = l.value("range", 0.0f);
        const auto spot = l.value("spot", nlohmann::json::object());
        g.innerConeAngle = spot.value("innerConeAngle", 0.0f);
        g.outerConeAngle = spot.value("outerConeAngle", 0.7853982f);
        out[node["name"].get<std::string>()] = g;
    }
    return out;
}

} // namespace dhdr::detail
