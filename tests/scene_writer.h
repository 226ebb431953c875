// Small glTF 2.0 files written by the tests themselves: a few triangles, a camera, lights,
// with whatever defect a test needs, so that no test depends on files from elsewhere.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace dhdr::test {

inline std::string base64(const std::vector<std::uint8_t>& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t n = std::uint32_t(bytes[i]) << 16 |
                                (i + 1 < bytes.size() ? std::uint32_t(bytes[i + 1]) << 8 : 0) |
                                (i + 2 < bytes.size() ? std::uint32_t(bytes[i + 2]) : 0);
        out += table[(n >> 18) & 63];
        out += table[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(n >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[n & 63] : '=';
    }
    return out;
}

// One mesh of triangles in a glTF document; nodes, cameras and extensions are the caller's.
struct GltfMesh {
    std::vector<std::array<float, 3>> positions, normals; // normals may be empty
    std::vector<std::uint32_t> indices;
};

// A document holding `mesh` as mesh 0 (one white material), its data in a data URI.
inline nlohmann::json gltfWithMesh(const GltfMesh& mesh) {
    using nlohmann::json;
    std::vector<std::uint8_t> bytes;
    auto append = [&](const void* data, size_t size) {
        const auto* p = static_cast<const std::uint8_t*>(data);
        bytes.insert(bytes.end(), p, p + size);
    };
    json doc;
    doc["asset"] = {{"version", "2.0"}};
    json views = json::array(), accessors = json::array(), attributes = json::object();
    auto addVec3 = [&](const std::vector<std::array<float, 3>>& v, const char* name) {
        const size_t offset = bytes.size();
        std::array<float, 3> lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
        for (const auto& p : v) {
            append(p.data(), 12);
            for (int c = 0; c < 3; ++c) {
                lo[size_t(c)] = std::min(lo[size_t(c)], p[size_t(c)]);
                hi[size_t(c)] = std::max(hi[size_t(c)], p[size_t(c)]);
            }
        }
        views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", v.size() * 12}});
        json a = {{"bufferView", views.size() - 1},
                  {"componentType", 5126},
                  {"count", v.size()},
                  {"type", "VEC3"}};
        if (std::string(name) == "POSITION") {
            a["min"] = lo;
            a["max"] = hi;
        }
        accessors.push_back(a);
        attributes[name] = accessors.size() - 1;
    };
    addVec3(mesh.positions, "POSITION");
    if (!mesh.normals.empty()) addVec3(mesh.normals, "NORMAL");
    const size_t offset = bytes.size();
    append(mesh.indices.data(), mesh.indices.size() * 4);
    views.push_back(
        {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", mesh.indices.size() * 4}});
    accessors.push_back({{"bufferView", views.size() - 1},
                         {"componentType", 5125},
                         {"count", mesh.indices.size()},
                         {"type", "SCALAR"}});
    doc["buffers"] = {{{"byteLength", bytes.size()},
                       {"uri", "data:application/octet-stream;base64," + base64(bytes)}}};
    doc["bufferViews"] = views;
    doc["accessors"] = accessors;
    doc["materials"] = {{{"name", "white"},
                         {"pbrMetallicRoughness",
                          {{"baseColorFactor", {0.8, 0.8, 0.8, 1.0}},
                           {"metallicFactor", 0.0},
                           {"roughnessFactor", 0.5}}}}};
    doc["meshes"] = {
        {{"name", "mesh"},
         {"primitives",
          {{{"attributes", attributes}, {"indices", accessors.size() - 1}, {"material", 0}}}}}};
    return doc;
}

// A 2 × 2 square in the plane z = 0, facing +Z, as two triangles.
inline GltfMesh squareMesh(float half = 1.0f) {
    GltfMesh m;
    m.positions = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

inline void writeJson(const std::string& path, const nlohmann::json& doc) {
    std::ofstream(path) << doc.dump(1);
}

} // namespace dhdr::test
