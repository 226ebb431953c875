#include "load/gltf_morph.h"

#include <cmath>

namespace dhdr::detail {

namespace {

using nlohmann::json;

const json* primitiveOf(const json& doc, int node, unsigned primitive) {
    if (!doc.contains("nodes") || !doc["nodes"].is_array() || node < 0 ||
        size_t(node) >= doc["nodes"].size())
        return nullptr;
    const json& n = doc["nodes"][size_t(node)];
    if (!n.is_object() || !n.contains("mesh") || !n["mesh"].is_number_unsigned()) return nullptr;
    const size_t m = n["mesh"].get<size_t>();
    if (!doc.contains("meshes") || !doc["meshes"].is_array() || m >= doc["meshes"].size())
        return nullptr;
    const json& mesh = doc["meshes"][m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array() ||
        primitive >= mesh["primitives"].size() || !mesh["primitives"][primitive].is_object())
        return nullptr;
    return &mesh["primitives"][primitive];
}

// An attribute's VEC3 (or VEC2) elements, `count` of them.
bool readAttribute(GltfBuffers& buffers, const json& attributes, const char* name, int want,
                   size_t count, std::vector<float>& out, std::string& error) {
    if (!attributes.contains(name) || !attributes[name].is_number_unsigned()) {
        error = std::string("has no ") + name + " accessor";
        return false;
    }
    int components = 0;
    if (!buffers.readFloats(attributes[name].get<size_t>(), out, components, error)) return false;
    if (components != want || (count > 0 && out.size() != count * size_t(want))) {
        error = std::string(name) + ": " +
                std::to_string(out.size() / size_t(std::max(components, 1))) + " elements of " +
                std::to_string(components) + " components, " + std::to_string(count) + " of " +
                std::to_string(want) + " expected";
        return false;
    }
    for (const float v : out)
        if (!std::isfinite(v)) {
            error = std::string(name) + " holds a value that is not a finite number";
            return false;
        }
    return true;
}

std::vector<glm::vec3> vec3s(const std::vector<float>& v) {
    std::vector<glm::vec3> out(v.size() / 3);
    for (size_t i = 0; i < out.size(); ++i)
        out[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    return out;
}

// The default weights: the node's, else the mesh's, else zeros (glTF 2.0 §3.7.2.2).
std::vector<double> defaultWeights(const json& doc, int node, size_t targets) {
    std::vector<double> w(targets, 0.0);
    const json& n = doc["nodes"][size_t(node)];
    const json& mesh = doc["meshes"][n["mesh"].get<size_t>()];
    const json* given = n.contains("weights")      ? &n["weights"]
                        : mesh.contains("weights") ? &mesh["weights"]
                                                   : nullptr;
    if (given && given->is_array() && given->size() == targets)
        for (size_t i = 0; i < targets; ++i)
            if ((*given)[i].is_number() && std::isfinite((*given)[i].get<double>()))
                w[i] = (*given)[i].get<double>();
    return w;
}

// The skin node `node` names, −1 when none.
int skinOf(const json& doc, int node) {
    const json& n = doc["nodes"][size_t(node)];
    return n.contains("skin") && n["skin"].is_number_unsigned() ? int(n["skin"].get<size_t>()) : -1;
}

} // namespace

bool gltfIsDeformed(const json& doc, int node, unsigned primitive) {
    const json* p = primitiveOf(doc, node, primitive);
    if (!p) return false;
    if (p->contains("targets") && (*p)["targets"].is_array() && !(*p)["targets"].empty())
        return true;
    return skinOf(doc, node) >= 0 && p->contains("attributes") && (*p)["attributes"].is_object() &&
           (*p)["attributes"].contains("JOINTS_0") && (*p)["attributes"].contains("WEIGHTS_0");
}

namespace {

// The primitive's JOINTS_0 and WEIGHTS_0 when its node is skinned (and has them).
bool readSkin(const json& doc, GltfBuffers& buffers, int node, const json& attributes, size_t count,
              MeshRest& rest, std::string& error) {
    rest.skin = skinOf(doc, node);
    if (rest.skin < 0 || !attributes.contains("JOINTS_0") || !attributes.contains("WEIGHTS_0")) {
        rest.skin = -1;
        return true;
    }
    std::vector<float> j, w;
    if (!readAttribute(buffers, attributes, "JOINTS_0", 4, count, j, error) ||
        !readAttribute(buffers, attributes, "WEIGHTS_0", 4, count, w, error))
        return false;
    for (size_t i = 0; i < count; ++i) {
        glm::u16vec4 joints;
        for (int c = 0; c < 4; ++c) {
            const float v = j[4 * i + size_t(c)];
            if (!(v >= 0.0f && v <= 65535.0f) || v != std::floor(v)) {
                error = "JOINTS_0 holds " + std::to_string(v) + ", not a joint index";
                return false;
            }
            joints[c] = std::uint16_t(v);
        }
        rest.joints.push_back(joints);
        rest.jointWeights.emplace_back(w[4 * i], w[4 * i + 1], w[4 * i + 2], w[4 * i + 3]);
    }
    return true;
}

} // namespace

namespace {

// COLOR_0 of the primitive, RGB or RGBA (alpha 1), when it has one.
bool readColors(GltfBuffers& buffers, const json& attributes, size_t count, Mesh& mesh,
                std::string& error) {
    mesh.colors.clear();
    if (!attributes.contains("COLOR_0")) return true;
    std::vector<float> v;
    int components = 0;
    if (!attributes["COLOR_0"].is_number_unsigned() ||
        !buffers.readFloats(attributes["COLOR_0"].get<size_t>(), v, components, error) ||
        (components != 3 && components != 4) || v.size() != count * size_t(components)) {
        error = "COLOR_0: " +
                (error.empty() ? "not " + std::to_string(count) + " RGB or RGBA colours" : error);
        return false;
    }
    for (size_t i = 0; i < count; ++i) {
        const float* c = &v[i * size_t(components)];
        glm::vec4 color(c[0], c[1], c[2], components == 4 ? c[3] : 1.0f);
        if (!std::isfinite(color.r + color.g + color.b + color.a)) color = glm::vec4(1.0f);
        mesh.colors.push_back(glm::clamp(color, 0.0f, 1.0f));
    }
    return true;
}

// POSITION, NORMAL (when `normals`), TEXCOORD_0 and _1 and COLOR_0 of the primitive; `count`:
// how many vertices it has.
bool readVertices(GltfBuffers& buffers, const json& attributes, bool normals, MeshRest& rest,
                  Mesh& mesh, size_t& count, std::string& error) {
    std::vector<float> v;
    if (!readAttribute(buffers, attributes, "POSITION", 3, 0, v, error)) return false;
    count = v.size() / 3;
    rest.positions = vec3s(v);
    if (normals) {
        if (!readAttribute(buffers, attributes, "NORMAL", 3, count, v, error)) return false;
        rest.normals = vec3s(v);
    }
    mesh.uvs.clear();
    if (attributes.contains("TEXCOORD_0")) {
        if (!readAttribute(buffers, attributes, "TEXCOORD_0", 2, count, v, error)) return false;
        for (size_t i = 0; i < count; ++i)
            mesh.uvs.emplace_back(v[2 * i], v[2 * i + 1]); // glTF's origin, as Mesh::uvs
    }
    mesh.uvs1.clear();
    if (!mesh.uvs.empty() && attributes.contains("TEXCOORD_1")) {
        if (!readAttribute(buffers, attributes, "TEXCOORD_1", 2, count, v, error)) return false;
        for (size_t i = 0; i < count; ++i)
            mesh.uvs1.emplace_back(v[2 * i], v[2 * i + 1]);
    }
    return readColors(buffers, attributes, count, mesh, error);
}

// The primitive's triangles (its indices, else its vertices in order), each index checked
// against its `count` vertices.
bool readTriangles(GltfBuffers& buffers, const json& p, size_t count, Mesh& mesh,
                   std::string& error) {
    std::vector<std::uint32_t> indices;
    if (p.contains("indices")) {
        if (!p["indices"].is_number_unsigned() ||
            !buffers.readIndices(p["indices"].get<size_t>(), indices, error))
            return false;
    } else {
        for (size_t i = 0; i < count; ++i)
            indices.push_back(std::uint32_t(i));
    }
    mesh.triangles.clear();
    for (size_t i = 0; i + 2 < indices.size(); i += 3) {
        if (indices[i] >= count || indices[i + 1] >= count || indices[i + 2] >= count) {
            error = "an index past its " + std::to_string(count) + " vertices";
            return false;
        }
        mesh.triangles.emplace_back(indices[i], indices[i + 1], indices[i + 2]);
    }
    return true;
}

// The morph targets' position (and, with `normals`, normal) offsets; an absent one is zero.
bool readTargets(GltfBuffers& buffers, const json& targets, size_t count, bool normals,
                 MeshRest& rest, std::string& error) {
    std::vector<float> v;
    for (size_t t = 0; t < targets.size(); ++t) {
        const std::string which = "target " + std::to_string(t) + ": ";
        if (!targets[t].is_object()) {
            error = which + "not an object";
            return false;
        }
        std::vector<glm::vec3> dp(count, glm::vec3(0.0f)), dn;
        if (targets[t].contains("POSITION")) {
            if (!readAttribute(buffers, targets[t], "POSITION", 3, count, v, error))
                return error = which + error, false;
            dp = vec3s(v);
        }
        if (normals) {
            dn.assign(count, glm::vec3(0.0f));
            if (targets[t].contains("NORMAL")) {
                if (!readAttribute(buffers, targets[t], "NORMAL", 3, count, v, error))
                    return error = which + error, false;
                dn = vec3s(v);
            }
            rest.normalTargets.push_back(std::move(dn));
        }
        rest.positionTargets.push_back(std::move(dp));
    }
    return true;
}

// Flat normals (glTF §3.7.2.1): every triangle its own three vertices.
void splitFlat(MeshRest& rest, Mesh& mesh) {
    MeshRest split = rest;
    split.positions.clear();
    for (auto& t : split.positionTargets)
        t.clear();
    split.joints.clear();
    split.jointWeights.clear();
    std::vector<glm::vec2> uvs, uvs1;
    std::vector<glm::vec4> colors;
    std::vector<glm::uvec3> triangles;
    for (const glm::uvec3& tri : mesh.triangles) {
        const unsigned first = unsigned(split.positions.size());
        for (const unsigned i : {tri.x, tri.y, tri.z}) {
            split.positions.push_back(rest.positions[i]);
            for (size_t t = 0; t < rest.positionTargets.size(); ++t)
                split.positionTargets[t].push_back(rest.positionTargets[t][i]);
            if (!mesh.uvs.empty()) uvs.push_back(mesh.uvs[i]);
            if (!mesh.uvs1.empty()) uvs1.push_back(mesh.uvs1[i]);
            if (!mesh.colors.empty()) colors.push_back(mesh.colors[i]);
            if (rest.skin >= 0) {
                split.joints.push_back(rest.joints[i]);
                split.jointWeights.push_back(rest.jointWeights[i]);
            }
        }
        triangles.emplace_back(first, first + 1, first + 2);
    }
    rest = std::move(split);
    mesh.uvs = std::move(uvs);
    mesh.uvs1 = std::move(uvs1);
    mesh.colors = std::move(colors);
    mesh.triangles = std::move(triangles);
}

} // namespace

bool gltfMorphPrimitive(const json& doc, GltfBuffers& buffers, int node, unsigned primitive,
                        MeshRest& rest, Mesh& mesh, std::string& error) {
    const json& p = *primitiveOf(doc, node, primitive);
    if (p.value("mode", 4) != 4) {
        error = "only triangle lists (mode 4) are morphed";
        return false;
    }
    if (!p.contains("attributes") || !p["attributes"].is_object()) {
        error = "has no attributes";
        return false;
    }
    const json& attributes = p["attributes"];
    const bool normals = attributes.contains("NORMAL");
    size_t count = 0;
    if (!readVertices(buffers, attributes, normals, rest, mesh, count, error) ||
        !readTriangles(buffers, p, count, mesh, error) ||
        !readSkin(doc, buffers, node, attributes, count, rest, error))
        return false;
    const json& targets = p.value("targets", json::array());
    if (!readTargets(buffers, targets, count, normals, rest, error)) return false;
    rest.weights = defaultWeights(doc, node, targets.size());
    rest.flatNormals = !normals;
    if (!normals) splitFlat(rest, mesh);
    const size_t vertices = rest.positions.size();
    rest.tangents.clear();
    rest.bitangents.clear();
    mesh.tangents.clear();
    mesh.bitangents.clear();
    mesh.positions.assign(vertices, glm::vec3(0.0f));
    mesh.normals.assign(vertices, glm::vec3(0.0f));
    return true;
}

} // namespace dhdr::detail
