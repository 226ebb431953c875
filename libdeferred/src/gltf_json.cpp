#include "gltf_json.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
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

} // namespace

std::map<std::string, float> gltfEmissiveStrengths(const std::string& path) {
    std::map<std::string, float> out;
    std::ifstream in(path, std::ios::binary);
    if (!in) return out;
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    const std::string text = glbJsonChunk(bytes);
    const nlohmann::json doc = nlohmann::json::parse(
        text.empty() ? std::string(bytes.begin(), bytes.end()) : text, nullptr, false);
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

} // namespace dhdr::detail
