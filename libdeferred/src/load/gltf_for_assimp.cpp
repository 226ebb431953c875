// What Assimp 5.2 is handed of a glTF file: its JSON without what dhdr reads itself, and a
// node tree too deep for Assimp's recursion flattened (declared in gltf_json.h).
#include "load/gltf_json.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <iterator>
#include <vector>

namespace dhdr::detail {

namespace {

// A node's local transform: its matrix, else translation · rotation · scale; a field of the
// wrong shape counts as absent (as the rest of the file, Assimp judges it).
glm::dmat4 localTransform(const nlohmann::json& node) {
    auto numbers = [&](const char* key, size_t count, std::vector<double>& out) {
        out.clear();
        if (!node.contains(key) || !node[key].is_array() || node[key].size() != count) return false;
        for (const auto& v : node[key]) {
            if (!v.is_number()) return false;
            out.push_back(v.get<double>());
        }
        return true;
    };
    std::vector<double> v;
    if (numbers("matrix", 16, v)) return glm::make_mat4(v.data());
    glm::dmat4 m(1.0);
    if (numbers("translation", 3, v)) m[3] = glm::dvec4(v[0], v[1], v[2], 1.0);
    if (numbers("rotation", 4, v)) m = m * glm::mat4_cast(glm::dquat(v[3], v[0], v[1], v[2]));
    if (numbers("scale", 3, v)) m = m * glm::scale(glm::dmat4(1.0), glm::dvec3(v[0], v[1], v[2]));
    return m;
}

// The children of node `n` that exist.
std::vector<size_t> childrenOf(const nlohmann::json& nodes, size_t n) {
    std::vector<size_t> out;
    const nlohmann::json& node = nodes[n];
    if (!node.is_object() || !node.contains("children") || !node["children"].is_array()) return out;
    for (const auto& c : node["children"])
        if (c.is_number_unsigned() && c.get<size_t>() < nodes.size())
            out.push_back(c.get<size_t>());
    return out;
}

// The children of every node, how deep the deepest lies and whether a node is the child of
// two.
struct NodeTreeShape {
    std::vector<std::vector<size_t>> children;
    int deepest = 0;
    bool shared = false;
};

// Depth of every node from the nodes no node names as a child, and cycles: a node on the
// current path met again (false with `error`). An explicit stack of (node, depth, next child to
// visit).
bool treeShape(const nlohmann::json& nodes, NodeTreeShape& shape, std::string& error) {
    const size_t count = nodes.size();
    std::vector<std::vector<size_t>>& children = shape.children;
    children.assign(count, {});
    std::vector<int> parents(count, 0);
    for (size_t n = 0; n < count; ++n) {
        children[n] = childrenOf(nodes, n);
        for (size_t c : children[n])
            ++parents[c];
    }
    enum : char { kUnseen, kOnPath, kDone };
    std::vector<char> state(count, kUnseen);
    auto walk = [&](size_t root) {
        std::vector<std::pair<size_t, size_t>> stack = {{root, 0}}; // node, next child index
        state[root] = kOnPath;
        while (!stack.empty()) {
            shape.deepest = std::max(shape.deepest, int(stack.size()));
            auto& [n, next] = stack.back();
            if (next == children[n].size()) {
                state[n] = kDone;
                stack.pop_back();
                continue;
            }
            const size_t c = children[n][next++];
            if (state[c] == kOnPath) {
                error = "node " + std::to_string(c) +
                        " is its own ancestor (the nodes form a cycle, not a tree)";
                return false;
            }
            if (state[c] == kDone) {
                shape.shared = true;
                continue;
            }
            state[c] = kOnPath;
            stack.emplace_back(c, 0);
        }
        return true;
    };
    for (size_t n = 0; n < count; ++n)
        if (parents[n] == 0 && !walk(n)) return false;
    // What no root reaches lies on a cycle (or hangs from one).
    for (size_t n = 0; n < count; ++n)
        if (state[n] == kUnseen && !walk(n)) return false;
    return true;
}

// The default scene's nodes, depth first in the file's order, each made a root with its world
// transform as its matrix, in `doc` (a copy of the document whose nodes are `nodes`). False
// when `doc` has no such scene to flatten.
bool flattenScene(nlohmann::json& doc, const nlohmann::json& nodes,
                  const std::vector<std::vector<size_t>>& children) {
    const size_t count = nodes.size();
    if (!doc.contains("scenes") || !doc["scenes"].is_array() || doc["scenes"].empty()) return false;
    const size_t sceneIndex =
        doc.contains("scene") && doc["scene"].is_number_unsigned() ? doc["scene"].get<size_t>() : 0;
    if (sceneIndex >= doc["scenes"].size() || !doc["scenes"][sceneIndex].is_object()) return false;
    nlohmann::json& scene = doc["scenes"][sceneIndex];
    if (!scene.contains("nodes") || !scene["nodes"].is_array()) return false;
    std::vector<std::pair<size_t, glm::dmat4>> stack;
    for (size_t i = scene["nodes"].size(); i-- > 0;)
        if (scene["nodes"][i].is_number_unsigned() && scene["nodes"][i].get<size_t>() < count)
            stack.emplace_back(scene["nodes"][i].get<size_t>(), glm::dmat4(1.0));
    std::vector<std::pair<size_t, glm::dmat4>> flat;
    while (!stack.empty()) {
        const auto [n, parent] = stack.back();
        stack.pop_back();
        const glm::dmat4 world = parent * localTransform(nodes[n]);
        flat.emplace_back(n, world);
        for (size_t i = children[n].size(); i-- > 0;)
            stack.emplace_back(children[n][i], world);
    }
    nlohmann::json roots = nlohmann::json::array();
    for (const auto& [n, world] : flat) {
        nlohmann::json& node = doc["nodes"][n];
        if (!node.is_object()) continue;
        for (const char* key : {"children", "translation", "rotation", "scale", "matrix"})
            node.erase(key);
        const double* m = glm::value_ptr(world);
        node["matrix"] = std::vector<double>(m, m + 16);
        roots.push_back(n);
    }
    scene["nodes"] = roots;
    return true;
}

} // namespace

bool gltfFlattenDeepNodes(const std::string& path, const nlohmann::json& original,
                          std::string& bytes, std::string& error) {
    bytes.clear();
    if (original.is_discarded() || !original.is_object() || !original.contains("nodes") ||
        !original["nodes"].is_array())
        return true;
    const nlohmann::json& nodes = original["nodes"];
    NodeTreeShape shape;
    if (!treeShape(nodes, shape, error)) return false;
    if (shape.deepest <= kMaxGltfNodeDepth) return true;
    if (shape.shared) {
        error = "a node is the child of two nodes (the nodes do not form a tree)";
        return false;
    }
    nlohmann::json doc = original;
    if (!flattenScene(doc, nodes, shape.children)) return true;
    bytes = gltfBytesWithJson(path, gltfForAssimp(doc));
    return true;
}

bool gltfHasAnimationOrSkins(const nlohmann::json& doc) {
    return doc.is_object() && (doc.contains("animations") || doc.contains("skins"));
}

nlohmann::json gltfForAssimp(nlohmann::json doc) {
    doc.erase("animations");
    doc.erase("skins");
    if (doc.contains("nodes") && doc["nodes"].is_array())
        for (auto& node : doc["nodes"])
            if (node.is_object()) node.erase("skin");
    return doc;
}

std::string gltfBytesWithJson(const std::string& path, const nlohmann::json& doc) {
    std::string text = doc.dump();
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> file((std::istreambuf_iterator<char>(in)),
                                 std::istreambuf_iterator<char>());
    const bool glb = !glbJsonChunk(file).empty();
    if (!glb) return text;
    // A binary glTF: header, the new JSON chunk padded with spaces to 4 bytes, then the
    // file's other chunks as they were.
    while (text.size() % 4 != 0)
        text += ' ';
    std::uint32_t oldLength = 0;
    std::memcpy(&oldLength, file.data() + 12, 4);
    const size_t rest = 20 + size_t(oldLength);
    const std::uint32_t jsonLength = std::uint32_t(text.size());
    const std::uint32_t total = std::uint32_t(12 + 8 + text.size() + (file.size() - rest));
    std::string bytes(file.data(), 8);
    bytes.append(reinterpret_cast<const char*>(&total), 4);
    bytes.append(reinterpret_cast<const char*>(&jsonLength), 4);
    bytes.append("JSON", 4);
    bytes += text;
    bytes.append(file.data() + rest, file.size() - rest);
    return bytes;
}

} // namespace dhdr::detail
