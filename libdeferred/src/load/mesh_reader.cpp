#include "load/mesh_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace dhdr::detail {

namespace {

// A vertex at infinity (or NaN, or beyond a float once transformed) has no place in a
// bounding box, a BVH or a camera framing: the file is refused.
bool finiteInWorld(const glm::dvec3& wp) {
    const double fmax = double(std::numeric_limits<float>::max());
    return std::abs(wp.x) <= fmax && std::abs(wp.y) <= fmax && std::abs(wp.z) <= fmax;
}

// Tangent frames (the file's, or CalcTangentSpace's from the UVs) move with the surface;
// Assimp's bitangent points up the image (+v in its flipped UVs).
void addTangentFrame(const aiMesh& am, unsigned v, const glm::dmat4& world, Mesh& mesh) {
    auto unit = [](const glm::dvec3& d) {
        const double len = glm::length(d);
        return len > 1e-12 && std::isfinite(len) ? glm::vec3(d / len) : glm::vec3(0.0f);
    };
    const aiVector3D& t = am.mTangents[v];
    const aiVector3D& b = am.mBitangents[v];
    mesh.tangents.push_back(unit(glm::dmat3(world) * glm::dvec3(t.x, t.y, t.z)));
    mesh.bitangents.push_back(unit(glm::dmat3(world) * glm::dvec3(b.x, b.y, b.z)));
}

glm::vec3 unitOrZero(const glm::dvec3& d) {
    const double len = glm::length(d);
    return len > 0.0 && std::isfinite(len) ? glm::vec3(d / len) : glm::vec3(0.0f);
}

// A flat triangle's tangent frame from its UVs, in world space (`tangent`, `bitangent`) and in
// the node's (`localTangent`, `localBitangent`): T along +u, B up the image, as Assimp
// computes them. Left as they are when the UVs are degenerate.
struct FlatFrame {
    glm::vec3 tangent{0.0f}, bitangent{0.0f}, localTangent{0.0f}, localBitangent{0.0f};
};

FlatFrame flatFrame(const Mesh& shared, const glm::uvec3& t, const glm::dvec3& a,
                    const glm::dvec3& b, const glm::dvec3& c, const glm::dmat4& world) {
    FlatFrame f;
    // Assimp's UVs (v up the image), from ours (v down).
    auto uv = [&](unsigned i) {
        return glm::dvec2(shared.uvs[i].x, 1.0 - double(shared.uvs[i].y));
    };
    const glm::dvec2 d1 = uv(t.y) - uv(t.x), d2 = uv(t.z) - uv(t.x);
    const glm::dvec3 e1 = glm::dmat3(world) * (b - a), e2 = glm::dmat3(world) * (c - a);
    const double det = d1.x * d2.y - d2.x * d1.y;
    if (det != 0.0) {
        f.tangent = unitOrZero((e1 * d2.y - e2 * d1.y) / det);
        f.bitangent = unitOrZero((e2 * d1.x - e1 * d2.x) / det);
        // The same in the node's space: the world's is linear in the edges.
        const glm::dvec3 l1 = b - a, l2 = c - a;
        f.localTangent = glm::vec3((l1 * d2.y - l2 * d1.y) / det);
        f.localBitangent = glm::vec3((l2 * d1.x - l1 * d2.x) / det);
    }
    return f;
}

// glTF 2.0 (§3.7.2.1): "When normals are not specified, client implementations MUST
// calculate flat normals". Each triangle gets three vertices of its own with its normal:
// the cross product of its edges in the file's space, turned by the normal matrix (so that
// under a mirroring node it stays on the front, whose winding the node reverses). With UVs,
// each triangle also gets its tangent frame from them (CalcTangentSpace needs normals).
// `rest`, when given, receives the same vertices in the node's space.
Mesh flatShaded(const Mesh& shared, const aiMesh& am, const glm::dmat4& world,
                const glm::dmat3& normalMatrix, MeshRest* rest) {
    MeshRest inNode;
    Mesh flat;
    flat.object = shared.object;
    flat.material = shared.material;
    const bool uvs = !shared.uvs.empty();
    for (const glm::uvec3& t : shared.triangles) {
        auto local = [&](unsigned i) {
            const aiVector3D& p = am.mVertices[i];
            return glm::dvec3(p.x, p.y, p.z);
        };
        const glm::dvec3 a = local(t.x), b = local(t.y), c = local(t.z);
        const glm::vec3 normal = unitOrZero(normalMatrix * glm::cross(b - a, c - a));
        const FlatFrame frame = uvs ? flatFrame(shared, t, a, b, c, world) : FlatFrame{};
        const unsigned first = unsigned(flat.positions.size());
        for (const unsigned i : {t.x, t.y, t.z}) {
            flat.positions.push_back(shared.positions[i]);
            flat.normals.push_back(normal);
            if (uvs) {
                flat.uvs.push_back(shared.uvs[i]);
                flat.tangents.push_back(frame.tangent);
                flat.bitangents.push_back(frame.bitangent);
            }
            if (!shared.uvs1.empty()) flat.uvs1.push_back(shared.uvs1[i]);
            if (!shared.colors.empty()) flat.colors.push_back(shared.colors[i]);
            if (!rest) continue;
            inNode.positions.push_back(glm::vec3(local(i)));
            inNode.normals.push_back(glm::vec3(glm::cross(b - a, c - a)));
            if (uvs) {
                inNode.tangents.push_back(frame.localTangent);
                inNode.bitangents.push_back(frame.localBitangent);
            }
        }
        flat.triangles.emplace_back(first, first + 1, first + 2);
    }
    if (rest) {
        inNode.node = rest->node;
        *rest = std::move(inNode);
    }
    return flat;
}

} // namespace

bool MeshReader::add(const aiMesh& am, const aiNode& node, unsigned primitive,
                     const glm::dmat4& world, const glm::dmat3& normalMatrix, int object,
                     std::string& error) {
    if (!(am.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) return true; // points and lines
    Mesh mesh;
    mesh.object = object;
    mesh.material = std::min<int>(int(am.mMaterialIndex), int(m_scene.materials.size()) - 1);
    if (!readVertices(am, node, world, normalMatrix, mesh, error)) return false;
    for (unsigned f = 0; f < am.mNumFaces; ++f) {
        const aiFace& face = am.mFaces[f];
        if (face.mNumIndices == 3)
            mesh.triangles.emplace_back(face.mIndices[0], face.mIndices[1], face.mIndices[2]);
    }
    MeshRest rest = m_rig.restOf(am, node);
    if (m_rig.deformed(rest, primitive)) {
        // Morphed or skinned: from the file itself (RigLoader::readDeformed).
        if (!m_rig.readDeformed(mesh, rest, world, primitive, error)) return false;
        keep(std::move(mesh), std::move(rest));
        return true;
    }
    if (!am.HasNormals())
        mesh = flatShaded(mesh, am, world, normalMatrix, m_rig.active() ? &rest : nullptr);
    if (mesh.tangents.size() != mesh.positions.size()) {
        mesh.tangents.clear();
        mesh.bitangents.clear();
        rest.tangents.clear();
        rest.bitangents.clear();
    }
    keep(std::move(mesh), std::move(rest));
    return true;
}

bool MeshReader::readVertices(const aiMesh& am, const aiNode& node, const glm::dmat4& world,
                              const glm::dmat3& normalMatrix, Mesh& mesh, std::string& error) {
    mesh.positions.reserve(am.mNumVertices);
    for (unsigned v = 0; v < am.mNumVertices; ++v) {
        const aiVector3D& p = am.mVertices[v];
        const glm::dvec3 wp(world * glm::dvec4(p.x, p.y, p.z, 1.0));
        if (!finiteInWorld(wp)) {
            char where[160];
            std::snprintf(where, sizeof where, "(%g, %g, %g) -> (%g, %g, %g)", p.x, p.y, p.z, wp.x,
                          wp.y, wp.z);
            error = m_path + ": mesh '" + am.mName.C_Str() + "' (node '" + node.mName.C_Str() +
                    "'): vertex " + std::to_string(v) +
                    " is not a finite position in world space " + where;
            return false;
        }
        mesh.positions.emplace_back(wp);
        if (am.HasNormals()) { // else flat normals (flatShaded)
            const aiVector3D& n = am.mNormals[v];
            const glm::dvec3 wn = normalMatrix * glm::dvec3(n.x, n.y, n.z);
            const double len = glm::length(wn);
            // Zero (or broken) normals stay zero: the triangle's own normal replaces them
            // where they are used (gbuffer_render.cpp).
            const bool usable = len > 1e-12 && std::isfinite(len);
            m_zeroNormals += !usable;
            mesh.normals.emplace_back(usable ? wn / len : glm::dvec3(0.0));
        }
        // Assimp's UVs have their origin at the image's bottom-left (it flips glTF's).
        if (am.HasTextureCoords(0))
            mesh.uvs.emplace_back(am.mTextureCoords[0][v].x, 1.0f - am.mTextureCoords[0][v].y);
        if (am.HasTextureCoords(0) && am.HasTextureCoords(1))
            mesh.uvs1.emplace_back(am.mTextureCoords[1][v].x, 1.0f - am.mTextureCoords[1][v].y);
        if (am.HasTangentsAndBitangents() && am.HasTextureCoords(0))
            addTangentFrame(am, v, world, mesh);
    }
    readColors(am, mesh);
    return true;
}

void MeshReader::readColors(const aiMesh& am, Mesh& mesh) const {
    if (!m_colors.read || !am.HasVertexColors(0)) return;
    bool anyAlpha = false;
    for (unsigned v = 0; v < am.mNumVertices; ++v) {
        const aiColor4D& c = am.mColors[0][v];
        mesh.colors.emplace_back(c.r, c.g, c.b, c.a);
        anyAlpha = anyAlpha || c.a != 0.0f;
    }
    // All alphas 0 where the file has RGB colours: Assimp's (VertexColors), made 1.
    for (glm::vec4& c : mesh.colors) {
        if (m_colors.rgbInFile && !anyAlpha) c.a = 1.0f;
        // Past float's range or NaN in the file: no colour.
        if (!std::isfinite(c.r + c.g + c.b + c.a)) c = glm::vec4(1.0f);
        c = glm::clamp(c, 0.0f, 1.0f);
    }
}

// A mesh with triangles joins the scene, and its rest the rig.
void MeshReader::keep(Mesh mesh, MeshRest rest) {
    if (mesh.triangles.empty()) return;
    m_scene.meshes.push_back(std::move(mesh));
    m_rig.keepMesh(std::move(rest));
}

} // namespace dhdr::detail
