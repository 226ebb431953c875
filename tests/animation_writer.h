// Animated glTF files written by the tests: a square that a node moves, a camera, and the
// samplers a test needs, each accessor in a buffer of its own (a data URI).
#pragma once

#include "scene_writer.h"

#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace dhdr::test {

// Appends `values` as a float accessor of `type` ("SCALAR", "VEC3"...) holding `count`
// elements (the count the file claims: a test may make it disagree); returns its index.
inline size_t addFloatAccessor(nlohmann::json& doc, const std::vector<float>& values,
                               const char* type, size_t count) {
    std::vector<std::uint8_t> bytes(values.size() * 4);
    std::memcpy(bytes.data(), values.data(), bytes.size());
    doc["buffers"].push_back({{"byteLength", bytes.size()},
                              {"uri", "data:application/octet-stream;base64," + base64(bytes)}});
    doc["bufferViews"].push_back(
        {{"buffer", doc["buffers"].size() - 1}, {"byteLength", bytes.size()}});
    doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1},
                                {"componentType", 5126},
                                {"count", count},
                                {"type", type}});
    return doc["accessors"].size() - 1;
}

inline size_t elementsOf(const char* type) {
    const std::string t = type;
    return t == "SCALAR" ? 1 : t == "VEC3" ? 3 : t == "VEC4" ? 4 : 1;
}

// Adds to animation `animation` (created when missing, named "anim<N>") a sampler of key
// `times` and `values` driving `path` of node `node`.
inline void addChannel(nlohmann::json& doc, size_t animation, int node, const char* path,
                       const std::vector<float>& times, const std::vector<float>& values,
                       const char* interpolation = "LINEAR", const char* type = nullptr) {
    if (!doc.contains("animations")) doc["animations"] = nlohmann::json::array();
    while (doc["animations"].size() <= animation)
        doc["animations"].push_back({{"name", "anim" + std::to_string(doc["animations"].size())},
                                     {"samplers", nlohmann::json::array()},
                                     {"channels", nlohmann::json::array()}});
    const char* valueType = type                              ? type
                            : std::string(path) == "rotation" ? "VEC4"
                            : std::string(path) == "weights"  ? "SCALAR"
                                                              : "VEC3";
    const size_t input = addFloatAccessor(doc, times, "SCALAR", times.size());
    const size_t output =
        addFloatAccessor(doc, values, valueType, values.size() / elementsOf(valueType));
    nlohmann::json& a = doc["animations"][animation];
    a["samplers"].push_back(
        {{"input", input}, {"output", output}, {"interpolation", interpolation}});
    a["channels"].push_back(
        {{"sampler", a["samplers"].size() - 1}, {"target", {{"node", node}, {"path", path}}}});
}

// The square of scene_writer.h (2 × 2, facing +Z) at node 0 "square", and an orthographic
// camera at node 1 "camera" at (0, 0, 5) looking down −Z whose image is 4 × 4 units: on a
// 64 × 64 image, 16 pixels a unit.
inline nlohmann::json squareAndCamera(float half = 0.5f) {
    nlohmann::json doc = gltfWithMesh(squareMesh(half));
    doc["cameras"] = {
        {{"name", "ortho"},
         {"type", "orthographic"},
         {"orthographic", {{"xmag", 2.0}, {"ymag", 2.0}, {"znear", 0.1}, {"zfar", 100.0}}}}};
    doc["nodes"] = {{{"name", "square"}, {"mesh", 0}},
                    {{"name", "camera"}, {"camera", 0}, {"translation", {0.0, 0.0, 5.0}}}};
    doc["scenes"] = {{{"nodes", {0, 1}}}};
    doc["scene"] = 0;
    return doc;
}

} // namespace dhdr::test

namespace dhdr::test {

// Gives mesh 0's primitive the morph targets `targets` (per target one POSITION delta per
// vertex, flattened x y z) and, when not empty, the mesh's default `weights`.
inline void addMorphTargets(nlohmann::json& doc, const std::vector<std::vector<float>>& targets,
                            const std::vector<float>& weights = {}) {
    nlohmann::json list = nlohmann::json::array();
    for (const std::vector<float>& t : targets)
        list.push_back({{"POSITION", addFloatAccessor(doc, t, "VEC3", t.size() / 3)}});
    doc["meshes"][0]["primitives"][0]["targets"] = list;
    if (!weights.empty()) doc["meshes"][0]["weights"] = weights;
}

} // namespace dhdr::test

namespace dhdr::test {

// Skins mesh 0's primitive at node 0 with skin 0 of `joints` (node indices): per vertex four
// joint indices and weights; `inverseBind` (16 numbers a joint, column-major) may be empty.
inline void addSkin(nlohmann::json& doc, const std::vector<int>& joints,
                    const std::vector<std::uint16_t>& vertexJoints,
                    const std::vector<float>& vertexWeights,
                    const std::vector<float>& inverseBind = {}) {
    std::vector<std::uint8_t> bytes(vertexJoints.size() * 2);
    std::memcpy(bytes.data(), vertexJoints.data(), bytes.size());
    doc["buffers"].push_back({{"byteLength", bytes.size()},
                              {"uri", "data:application/octet-stream;base64," + base64(bytes)}});
    doc["bufferViews"].push_back(
        {{"buffer", doc["buffers"].size() - 1}, {"byteLength", bytes.size()}});
    doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1},
                                {"componentType", 5123},
                                {"count", vertexJoints.size() / 4},
                                {"type", "VEC4"}});
    nlohmann::json& attributes = doc["meshes"][0]["primitives"][0]["attributes"];
    attributes["JOINTS_0"] = doc["accessors"].size() - 1;
    attributes["WEIGHTS_0"] =
        addFloatAccessor(doc, vertexWeights, "VEC4", vertexWeights.size() / 4);
    nlohmann::json skin = {{"joints", joints}};
    if (!inverseBind.empty())
        skin["inverseBindMatrices"] = addFloatAccessor(doc, inverseBind, "MAT4", joints.size());
    doc["skins"] = {skin};
    doc["nodes"][0]["skin"] = 0;
}

} // namespace dhdr::test

namespace dhdr::test {

// Makes node 2's mesh glow (a copy of mesh 0 with an emissive material) and hangs a point light
// (KHR_lights_punctual, intensity 2) under node 2 at `lampOffset` in its space, so that both of
// the scene's own kinds of light ride with whatever moves node 2.
inline nlohmann::json withGlowAndLamp(nlohmann::json doc, float lampOffset) {
    doc["materials"].push_back({{"name", "glow"}, {"emissiveFactor", {1.0, 0.8, 0.6}}});
    doc["meshes"].push_back(doc["meshes"][0]);
    doc["meshes"][1]["primitives"][0]["material"] = 1;
    doc["nodes"][2]["mesh"] = 1;
    doc["extensionsUsed"] = {"KHR_lights_punctual"};
    doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 2.0}}};
    doc["nodes"].push_back({{"name", "lamp"},
                            {"translation", {0.0, 0.0, lampOffset}},
                            {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    doc["nodes"][2]["children"] = {3};
    return doc;
}

} // namespace dhdr::test
