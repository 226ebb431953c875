#include "load/gltf_json.h"
#include "load/rig_loader.h"
#include "load/texture_loader.h"

#include <algorithm>
#include <assimp/DefaultIOSystem.h>
#include <assimp/GltfMaterial.h>
#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace dhdr {

namespace {

glm::dmat4 toGlm(const aiMatrix4x4& m) {
    // Assimp is row-major with translation in a4, b4, c4; glm is column-major.
    glm::dmat4 out;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            out[c][r] = m[r][c];
    return out;
}

bool isGltf(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    return ext == ".gltf" || ext == ".glb";
}

// Assimp 5.2's MTL parser stops at the `aniso` and `anisor` lines that Blender writes into
// every material ("Cannot parse string \"niso\" as a real number"), so no Blender OBJ loads.
// MTL files are handed to it without those lines; the rest (Pm, Pr, Ke...) it reads itself.
//
// It also hands Assimp a replacement for the scene file itself when one is set (a glTF whose
// deep node tree dhdr flattened, gltfFlattenDeepNodes).
class MtlCleaningIOSystem : public Assimp::DefaultIOSystem {
public:
    void replace(const std::string& path, std::string bytes) {
        m_replaced = path;
        m_bytes = std::move(bytes);
    }

    Assimp::IOStream* Open(const char* file, const char* mode) override {
        const std::string path = file;
        if (!m_bytes.empty() && sameFile(path, m_replaced)) return memory(m_bytes);
        std::string ext = std::filesystem::path(path).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
        if (ext != ".mtl") return Assimp::DefaultIOSystem::Open(file, mode);
        std::ifstream in(path, std::ios::binary);
        if (!in) return nullptr;
        std::string text, line;
        while (std::getline(in, line)) {
            std::istringstream words(line);
            std::string key;
            words >> key;
            if (key == "aniso" || key == "anisor") continue;
            text += line + "\n";
        }
        return memory(text);
    }

private:
    static Assimp::IOStream* memory(const std::string& text) {
        auto* bytes = new uint8_t[text.size() + 1];
        std::memcpy(bytes, text.data(), text.size() + 1);
        return new Assimp::MemoryIOStream(bytes, text.size(), true);
    }

    static bool sameFile(const std::string& a, const std::string& b) {
        std::error_code ec;
        return a == b || std::filesystem::equivalent(a, b, ec);
    }

    std::string m_replaced, m_bytes;
};

const nlohmann::json kNoJson = nlohmann::json(nlohmann::json::value_t::discarded);

class SceneBuilder {
public:
    // `doc`: the glTF file's JSON (gltfJson), discarded for other files.
    SceneBuilder(const aiScene& ai, const std::string& path, const nlohmann::json& doc,
                 const SceneOptions& options, Scene& scene)
        : m_ai(ai), m_path(path), m_doc(doc), m_options(options), m_scene(scene),
          m_gltf(isGltf(path)) {}

    bool build(std::string& error) {
        loadMaterials();
        if (!m_rig.error().empty()) {
            error = m_rig.error();
            return false;
        }
        if (!visitAll(error)) return false;
        nameUnnamed();
        if (!reportUnreadTextures(error)) return false;
        if (m_zeroNormals > 0)
            m_scene.warnings.push_back(
                std::to_string(m_zeroNormals) +
                " vertex normals in the file have zero length; their triangles are shaded with "
                "the geometric normal");
        loadCameras();
        if (!loadLights(error)) return false;
        if (m_rig.active()) m_scene.rig = m_rig.finish();
        return true;
    }

private:
    void loadMaterials() {
        const auto strengths =
            m_gltf ? detail::gltfEmissiveStrengths(m_doc) : std::map<std::string, float>{};
        const auto textures = m_gltf ? detail::gltfMaterialTextures(m_doc)
                                     : std::map<std::string, detail::GltfMaterialTextures>{};
        for (unsigned i = 0; i < m_ai.mNumMaterials; ++i) {
            const aiMaterial& am = *m_ai.mMaterials[i];
            Material m;
            m.name = am.GetName().C_Str();
            aiColor4D base;
            if (am.Get(AI_MATKEY_BASE_COLOR, base) == AI_SUCCESS ||
                am.Get(AI_MATKEY_COLOR_DIFFUSE, base) == AI_SUCCESS) {
                m.baseColor = glm::vec3(base.r, base.g, base.b);
                m.alpha = base.a;
            }
            if (m_gltf) {
                aiString mode;
                if (am.Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS) {
                    const std::string name = mode.C_Str();
                    m.alphaMode = name == "BLEND"  ? AlphaMode::Blend
                                  : name == "MASK" ? AlphaMode::Mask
                                                   : AlphaMode::Opaque;
                }
                float cutoff = 0.5f;
                if (am.Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff) == AI_SUCCESS)
                    m.alphaCutoff = cutoff;
            } else {
                // OBJ/MTL: Assimp reports d (or 1 − Tr) as the opacity; below 1 it blends.
                float opacity = 1.0f;
                if (am.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && opacity < 1.0f) {
                    m.alpha = std::clamp(opacity, 0.0f, 1.0f);
                    m.alphaMode = AlphaMode::Blend;
                }
            }
            float metallic = 0.0f, roughness = 1.0f;
            // glTF's factors, or the MTL's PBR extension (Pm, Pr) that Assimp reports the same.
            if (am.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == AI_SUCCESS) {
                m.metallic = metallic;
                float shininess = 0.0f;
                if (am.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness) == AI_SUCCESS)
                    m.roughness = roughness;
                else if (!m_gltf && am.Get(AI_MATKEY_SHININESS, shininess) == AI_SUCCESS)
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
            aiColor3D emissive(0.0f, 0.0f, 0.0f);
            am.Get(AI_MATKEY_COLOR_EMISSIVE, emissive);
            float strength = 1.0f;
            // Assimp 5.2 drops KHR_materials_emissive_strength; newer ones report it here.
            if (am.Get(AI_MATKEY_EMISSIVE_INTENSITY, strength) != AI_SUCCESS) {
                const auto it = strengths.find(m.name);
                strength = it != strengths.end() ? it->second : 1.0f;
            }
            m.emission = glm::vec3(emissive.r, emissive.g, emissive.b) * strength;

            const auto t = textures.find(m.name);
            const detail::GltfMaterialTextures transforms =
                t != textures.end() ? t->second : detail::GltfMaterialTextures{};
            aiString texPath;
            if (am.GetTexture(aiTextureType_BASE_COLOR, 0, &texPath) == AI_SUCCESS ||
                am.GetTexture(aiTextureType_DIFFUSE, 0, &texPath) == AI_SUCCESS) {
                m.baseColorTexture.texture = loadTexture(texPath.C_Str(), true, "base colour");
                m.baseColorTexture.transform = transforms.baseColor;
            }
            if (am.GetTexture(aiTextureType_EMISSIVE, 0, &texPath) == AI_SUCCESS) {
                m.emissiveTexture.texture = loadTexture(texPath.C_Str(), true, "emissive");
                m.emissiveTexture.transform = transforms.emissive;
            }
            if (am.GetTexture(aiTextureType_NORMALS, 0, &texPath) == AI_SUCCESS) {
                m.normalTexture.texture = loadTexture(texPath.C_Str(), false, "normal");
                m.normalTexture.transform = transforms.normal;
                m.normalScale = transforms.normalScale;
            }
            m_scene.materials.push_back(m);
        }
        if (m_scene.materials.empty()) m_scene.materials.push_back(Material{});
    }

    // A texture that cannot be read (missing, undecodable) does not stop the render: the
    // material shows magenta (1, 0, 1) times its factor there, as Blender shows a missing
    // texture in pink, and a normal map is left out; reportUnreadTextures warns, naming the file
    // and the material, or with SceneOptions::strict fails.
    // Returns the index of the texture in Scene::textures, or −1.
    int loadTexture(const std::string& ref, bool srgb, const char* slot) {
        // The same file can be a colour (sRGB) and a data texture: one decoding of each.
        const std::string key = (srgb ? "srgb:" : "data:") + ref;
        if (auto it = m_unread.find(key); it != m_unread.end()) return unread(it->second, slot);
        if (auto it = m_textureIndex.find(key); it != m_textureIndex.end()) return it->second;
        std::string why;
        int index = -1;
        if (!decodeTexture(ref, srgb, index, why)) {
            m_unread[key] = why;
            return unread(why, slot);
        }
        m_textureIndex[key] = index;
        return index;
    }

    // Records an unread texture of the material being loaded; the index to use in its place:
    // the magenta one for colours, none for a normal map.
    int unread(const std::string& why, const char* slot) {
        const bool normal = std::string(slot) == "normal";
        m_unreadUses.push_back({m_scene.materials.size(), slot, why});
        if (normal) return -1;
        if (m_missingTexture < 0) {
            Texture magenta;
            magenta.name = "dhdr:missing texture";
            magenta.width = magenta.height = 1;
            magenta.rgba = {1.0f, 0.0f, 1.0f, 1.0f};
            m_missingTexture = int(m_scene.textures.size());
            m_scene.textures.push_back(std::move(magenta));
        }
        return m_missingTexture;
    }

    // After the materials have their names: one warning per unread texture use, naming the
    // texture (OpenImageIO's message names the file) and the material; with strict, an error.
    bool reportUnreadTextures(std::string& error) {
        for (const UnreadTexture& u : m_unreadUses) {
            const std::string material = m_scene.materials[u.material].name;
            const std::string what =
                "material '" + material + "', " + u.slot + " texture: " + u.why;
            if (m_options.strict) {
                error = m_path + ": " + what + " (without --strict it would be " +
                        (u.slot == std::string("normal") ? "left out" : "shown magenta") + ")";
                return false;
            }
            m_scene.warnings.push_back(
                what + (u.slot == std::string("normal")
                            ? "; the normal map is left out"
                            : "; shown as magenta (1, 0, 1) times the material's factor"));
        }
        return true;
    }

    bool decodeTexture(const std::string& ref, bool srgb, int& index, std::string& error) {
        Texture texture;
        if (const aiTexture* embedded = m_ai.GetEmbeddedTexture(ref.c_str())) {
            if (embedded->mHeight != 0) {
                error = ref + ": uncompressed embedded textures are not supported";
                return false;
            }
            const std::string hint = std::string("embedded.") + embedded->achFormatHint;
            if (!detail::loadTexture(texture, hint, embedded->pcData, embedded->mWidth, srgb,
                                     error))
                return false;
            texture.name = ref;
        } else {
            auto file = std::filesystem::path(m_path).parent_path() / ref;
            // Files written on Windows name textures with backslashes (".\\wall.jpg").
            if (std::string unix = ref;
                !std::filesystem::exists(file) && unix.find('\\') != std::string::npos) {
                std::replace(unix.begin(), unix.end(), '\\', '/');
                file = std::filesystem::path(m_path).parent_path() / unix;
            }
            if (!detail::loadTexture(texture, file.string(), nullptr, 0, srgb, error)) return false;
        }
        index = int(m_scene.textures.size());
        m_scene.textures.push_back(std::move(texture));
        return true;
    }

    // Calls visit(node, world transform) for every node, depth first in the file's order,
    // until it returns false. An explicit stack: a file may nest nodes deeper than the call
    // stack would survive.
    template <class Visit>
    void forEachNode(Visit visit) const {
        std::vector<std::pair<const aiNode*, glm::dmat4>> stack = {
            {m_ai.mRootNode, glm::dmat4(1.0)}};
        while (!stack.empty()) {
            const auto [node, parent] = stack.back();
            stack.pop_back();
            const glm::dmat4 world = parent * toGlm(node->mTransformation);
            if (!visit(*node, world)) return;
            for (unsigned i = node->mNumChildren; i-- > 0;)
                stack.emplace_back(node->mChildren[i], world);
        }
    }

    bool visitAll(std::string& error) {
        bool ok = true;
        forEachNode([&](const aiNode& n, const glm::dmat4& world) {
            const aiNode* node = &n;
            if (node->mNumMeshes > 0) {
                const int object = int(m_scene.objectNames.size());
                // Unnamed: the mesh's name, else a generated one (nameUnnamed).
                std::string name = shownName(node->mName.C_Str(), m_nodeNames, "nodes");
                if (name.empty())
                    name = shownName(m_ai.mMeshes[node->mMeshes[0]]->mName.C_Str(), m_meshNames,
                                     "meshes");
                m_scene.objectNames.push_back(name);
                // The inverse transpose, scaled to its largest entry: a node scaled by 1e38
                // keeps usable normals (only their direction matters).
                glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(world)));
                double largest = 0.0;
                for (int c = 0; c < 3; ++c)
                    for (int r = 0; r < 3; ++r)
                        largest = std::max(largest, std::abs(normalMatrix[c][r]));
                if (largest > 0.0 && std::isfinite(largest)) normalMatrix /= largest;
                for (unsigned i = 0; i < node->mNumMeshes && ok; ++i)
                    ok = addMesh(*m_ai.mMeshes[node->mMeshes[i]], *node, i, world, normalMatrix,
                                 object, error);
            }
            return ok;
        });
        return ok;
    }

    // `primitive`: the place of `am` among its node's meshes, the glTF primitive it is.
    bool addMesh(const aiMesh& am, const aiNode& node, unsigned primitive, const glm::dmat4& world,
                 const glm::dmat3& normalMatrix, int object, std::string& error) {
        if (!(am.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) return true; // points and lines
        Mesh mesh;
        mesh.object = object;
        mesh.material = std::min<int>(int(am.mMaterialIndex), int(m_scene.materials.size()) - 1);
        mesh.positions.reserve(am.mNumVertices);
        for (unsigned v = 0; v < am.mNumVertices; ++v) {
            const aiVector3D& p = am.mVertices[v];
            const glm::dvec3 wp(world * glm::dvec4(p.x, p.y, p.z, 1.0));
            // A vertex at infinity (or NaN, or beyond a float once transformed) has no place
            // in a bounding box, a BVH or a camera framing: the file is refused.
            const double fmax = double(std::numeric_limits<float>::max());
            if (!(std::abs(wp.x) <= fmax && std::abs(wp.y) <= fmax && std::abs(wp.z) <= fmax)) {
                char where[160];
                std::snprintf(where, sizeof where, "(%g, %g, %g) -> (%g, %g, %g)", p.x, p.y, p.z,
                              wp.x, wp.y, wp.z);
                error = m_path + ": mesh '" + am.mName.C_Str() + "' (node '" + node.mName.C_Str() +
                        "'): vertex " + std::to_string(v) +
                        " is not a finite position in world space " + where;
                return false;
            }
            mesh.positions.emplace_back(wp);
            if (am.HasNormals()) { // else flat normals, below
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
            // Tangent frames (the file's, or CalcTangentSpace's from the UVs) move with the
            // surface; Assimp's bitangent points up the image (+v in its flipped UVs).
            if (am.HasTangentsAndBitangents() && am.HasTextureCoords(0)) {
                auto unit = [](const glm::dvec3& d) {
                    const double len = glm::length(d);
                    return len > 1e-12 && std::isfinite(len) ? glm::vec3(d / len) : glm::vec3(0.0f);
                };
                const aiVector3D& t = am.mTangents[v];
                const aiVector3D& b = am.mBitangents[v];
                mesh.tangents.push_back(unit(glm::dmat3(world) * glm::dvec3(t.x, t.y, t.z)));
                mesh.bitangents.push_back(unit(glm::dmat3(world) * glm::dvec3(b.x, b.y, b.z)));
            }
        }
        for (unsigned f = 0; f < am.mNumFaces; ++f) {
            const aiFace& face = am.mFaces[f];
            if (face.mNumIndices == 3)
                mesh.triangles.emplace_back(face.mIndices[0], face.mIndices[1], face.mIndices[2]);
        }
        MeshRest rest = m_rig.restOf(am, node);
        if (m_rig.deformed(rest, primitive)) {
            // Morphed or skinned: from the file itself (RigLoader::readDeformed).
            if (!m_rig.readDeformed(mesh, rest, world, primitive, error)) return false;
            if (mesh.triangles.empty()) return true;
            m_scene.meshes.push_back(std::move(mesh));
            m_rig.keepMesh(std::move(rest));
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
        if (mesh.triangles.empty()) return true;
        m_scene.meshes.push_back(std::move(mesh));
        m_rig.keepMesh(std::move(rest));
        return true;
    }

    // A name as the file gives it: empty for one Assimp made up for an unnamed glTF element
    // ("nodes[3]", "meshes[0]"), unless the file itself uses that name.
    std::string shownName(const std::string& name, const std::set<std::string>& given,
                          const std::string& array) const {
        if (!m_gltf || given.count(name) || name.rfind(array + "[", 0) != 0) return name;
        return {};
    }

    // Blender's naming of datablocks, so that Cryptomatte manifests and the G-buffer's name
    // tables hold no empty name and no name twice: a name the file gives keeps it at its
    // first use; an unnamed object or material is "Object" or "Material", and a name already
    // taken gets the first free ".001", ".002"... suffix ("Object.001", "box.001").
    static void blenderNames(std::vector<std::string*> names, const std::string& fallback) {
        std::set<std::string> taken;
        std::vector<bool> keep(names.size(), false);
        for (size_t i = 0; i < names.size(); ++i)
            keep[i] = !names[i]->empty() && taken.insert(*names[i]).second;
        for (size_t i = 0; i < names.size(); ++i) {
            if (keep[i]) continue;
            const std::string base = names[i]->empty() ? fallback : *names[i];
            std::string name = base;
            for (int k = 1; taken.count(name); ++k) {
                char suffix[16];
                std::snprintf(suffix, sizeof suffix, ".%03d", k);
                name = base + suffix;
            }
            taken.insert(name);
            *names[i] = name;
        }
    }

    void nameUnnamed() {
        std::vector<std::string*> objects, materials;
        for (std::string& name : m_scene.objectNames)
            objects.push_back(&name);
        for (Material& m : m_scene.materials)
            materials.push_back(&m.name);
        blenderNames(objects, "Object");
        blenderNames(materials, "Material");
    }

    // glTF 2.0 (§3.7.2.1): "When normals are not specified, client implementations MUST
    // calculate flat normals". Each triangle gets three vertices of its own with its normal:
    // the cross product of its edges in the file's space, turned by the normal matrix (so that
    // under a mirroring node it stays on the front, whose winding the node reverses). With UVs,
    // each triangle also gets its tangent frame from them (CalcTangentSpace needs normals):
    // T along +u, B up the image, as Assimp computes them.
    // `rest`, when given, receives the same vertices in the node's space.
    static Mesh flatShaded(const Mesh& shared, const aiMesh& am, const glm::dmat4& world,
                           const glm::dmat3& normalMatrix, MeshRest* rest) {
        MeshRest inNode;
        Mesh flat;
        flat.object = shared.object;
        flat.material = shared.material;
        const bool uvs = !shared.uvs.empty();
        auto unit = [](const glm::dvec3& d) {
            const double len = glm::length(d);
            return len > 0.0 && std::isfinite(len) ? glm::vec3(d / len) : glm::vec3(0.0f);
        };
        for (const glm::uvec3& t : shared.triangles) {
            auto local = [&](unsigned i) {
                const aiVector3D& p = am.mVertices[i];
                return glm::dvec3(p.x, p.y, p.z);
            };
            const glm::dvec3 a = local(t.x), b = local(t.y), c = local(t.z);
            const glm::vec3 normal = unit(normalMatrix * glm::cross(b - a, c - a));
            glm::vec3 tangent(0.0f), bitangent(0.0f), localTangent(0.0f), localBitangent(0.0f);
            if (uvs) {
                // Assimp's UVs (v up the image), from ours (v down).
                auto uv = [&](unsigned i) {
                    return glm::dvec2(shared.uvs[i].x, 1.0 - double(shared.uvs[i].y));
                };
                const glm::dvec2 d1 = uv(t.y) - uv(t.x), d2 = uv(t.z) - uv(t.x);
                const glm::dvec3 e1 = glm::dmat3(world) * (b - a), e2 = glm::dmat3(world) * (c - a);
                const double det = d1.x * d2.y - d2.x * d1.y;
                if (det != 0.0) {
                    tangent = unit((e1 * d2.y - e2 * d1.y) / det);
                    bitangent = unit((e2 * d1.x - e1 * d2.x) / det);
                    // The same in the node's space: the world's is linear in the edges.
                    const glm::dvec3 l1 = b - a, l2 = c - a;
                    localTangent = glm::vec3((l1 * d2.y - l2 * d1.y) / det);
                    localBitangent = glm::vec3((l2 * d1.x - l1 * d2.x) / det);
                }
            }
            const unsigned first = unsigned(flat.positions.size());
            for (const unsigned i : {t.x, t.y, t.z}) {
                flat.positions.push_back(shared.positions[i]);
                flat.normals.push_back(normal);
                if (uvs) {
                    flat.uvs.push_back(shared.uvs[i]);
                    flat.tangents.push_back(tangent);
                    flat.bitangents.push_back(bitangent);
                }
                if (!rest) continue;
                inNode.positions.push_back(glm::vec3(local(i)));
                inNode.normals.push_back(glm::vec3(glm::cross(b - a, c - a)));
                if (uvs) {
                    inNode.tangents.push_back(localTangent);
                    inNode.bitangents.push_back(localBitangent);
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

    // The world transform of the first node named `name`, depth first; identity when none is.
    glm::dmat4 nodeWorld(const aiString& name) const {
        glm::dmat4 found(1.0);
        forEachNode([&](const aiNode& node, const glm::dmat4& world) {
            if (node.mName != name) return true;
            found = world;
            return false;
        });
        return found;
    }

    void loadCameras() {
        // Assimp 5.2 passes a glTF camera's numbers through floats, folds its aspect ratio into
        // the field of view and reports an absent zfar as a number: glTF cameras come from the
        // file itself (placement from the node), others from Assimp.
        const auto fromFile =
            m_gltf ? detail::gltfCamerasByNode(m_doc) : std::map<std::string, detail::GltfCamera>{};
        for (unsigned i = 0; i < m_ai.mNumCameras; ++i) {
            const aiCamera& ac = *m_ai.mCameras[i];
            const glm::dmat4 world = nodeWorld(ac.mName);
            SceneCamera sc;
            sc.name = ac.mName.C_Str();
            sc.aspect = ac.mAspect;
            sc.camera.znear = ac.mClipPlaneNear > 0.0f ? ac.mClipPlaneNear : 0.01;
            sc.camera.zfar = ac.mClipPlaneFar > sc.camera.znear ? ac.mClipPlaneFar : 1000.0;
            const auto file = fromFile.find(sc.name);
            if (file != fromFile.end()) {
                // A glTF camera sits at its node, looking down −Z.
                const detail::GltfCamera& g = file->second;
                sc.camera.cameraToWorld = world;
                sc.problem = g.problem;
                sc.camera.orthographic = g.orthographic;
                sc.camera.znear = g.znear;
                if (g.orthographic) {
                    sc.camera.ymag = g.ymag;
                    sc.camera.zfar = g.zfar;
                    sc.aspect = g.ymag != 0.0 ? g.xmag / g.ymag : 0.0;
                    if (sc.problem.empty() && !(g.xmag > 0.0))
                        sc.problem =
                            "its xmag, " + std::to_string(g.xmag) + ", is not a positive number";
                } else {
                    sc.camera.yfov = g.yfov;
                    sc.aspect = g.aspectRatio;
                    // No zfar (an infinite projection in glTF): Assimp's far plane, as before,
                    // if it lies beyond the near one.
                    if (g.zfar != 0.0)
                        sc.camera.zfar = g.zfar;
                    else if (!(sc.camera.zfar > g.znear))
                        sc.camera.zfar = std::max(1000.0, 1000.0 * g.znear);
                }
            } else if (m_gltf) {
                // An unnamed node's camera: Assimp's numbers. Assimp 5.2's glTF importer
                // copies the node's translation into mPosition (applying it would move the
                // camera twice) and reports yfov · aspect as mHorizontalFOV.
                sc.camera.cameraToWorld = world;
                sc.camera.yfov =
                    ac.mAspect > 0.0f ? ac.mHorizontalFOV / ac.mAspect : ac.mHorizontalFOV;
                // An orthographic glTF camera: Assimp gives xmag as mOrthographicWidth and
                // xmag / ymag as mAspect.
                if (ac.mOrthographicWidth > 0.0f) {
                    sc.camera.orthographic = true;
                    sc.camera.ymag = ac.mAspect > 0.0f ? ac.mOrthographicWidth / ac.mAspect
                                                       : ac.mOrthographicWidth;
                }
            } else {
                // Assimp's documented convention: a camera in its node's space, and half the
                // horizontal angle.
                const glm::dvec3 eye(ac.mPosition.x, ac.mPosition.y, ac.mPosition.z);
                const glm::dvec3 look(ac.mLookAt.x, ac.mLookAt.y, ac.mLookAt.z);
                const glm::dvec3 up(ac.mUp.x, ac.mUp.y, ac.mUp.z);
                sc.camera.cameraToWorld = world * glm::inverse(glm::lookAt(eye, eye + look, up));
                const double aspect = ac.mAspect > 0.0f ? ac.mAspect : 1.0;
                sc.camera.yfov = 2.0 * std::atan(std::tan(double(ac.mHorizontalFOV)) / aspect);
            }
            if (sc.problem.empty()) sc.problem = sc.camera.problem();
            if (sc.problem.empty() && !(std::isfinite(sc.aspect) && sc.aspect >= 0.0))
                sc.problem = "its aspect ratio is not a positive number";
            if (!sc.problem.empty())
                m_scene.warnings.push_back("camera '" + sc.name +
                                           "' cannot be rendered from: " + sc.problem);
            m_scene.cameras.push_back(sc);
            // A glTF camera sits at its node: it moves with it (others are not animated).
            m_rig.keepCamera(ac.mName);
        }
    }

    bool loadLights(std::string& error) {
        // Assimp 5.2 folds a glTF light's intensity into its colour and drops its range, so
        // for glTF the light's own fields come from the file; placement from the node.
        std::map<std::string, detail::GltfLight> fromFile;
        if (m_gltf && !detail::gltfLightsByNode(m_doc, fromFile, error)) {
            error = m_path + ": " + error;
            return false;
        }
        for (unsigned i = 0; i < m_ai.mNumLights; ++i) {
            const aiLight& al = *m_ai.mLights[i];
            const glm::dmat4 world = nodeWorld(al.mName);
            Light light;
            light.name = al.mName.C_Str();
            light.position =
                glm::vec3(world * glm::dvec4(al.mPosition.x, al.mPosition.y, al.mPosition.z, 1.0));
            const glm::dvec3 dir(
                world * glm::dvec4(al.mDirection.x, al.mDirection.y, al.mDirection.z, 0.0));
            light.direction = glm::length(dir) > 0.0 ? glm::vec3(glm::normalize(dir))
                                                     : glm::vec3(0.0f, 0.0f, -1.0f);
            switch (al.mType) {
            case aiLightSource_DIRECTIONAL:
                light.type = LightType::Directional;
                break;
            case aiLightSource_SPOT:
                light.type = LightType::Spot;
                break;
            case aiLightSource_AMBIENT:
                light.type = LightType::Ambient;
                break;
            default:
                light.type = LightType::Point;
                break;
            }
            const auto it = fromFile.find(light.name);
            if (it != fromFile.end()) {
                const detail::GltfLight& g = it->second;
                light.color = g.color;
                light.intensity = g.intensity;
                if (g.range > 0.0f) light.range = g.range;
                light.innerConeAngle = g.innerConeAngle;
                light.outerConeAngle = g.outerConeAngle;
            } else {
                const glm::vec3 c(al.mColorDiffuse.r, al.mColorDiffuse.g, al.mColorDiffuse.b);
                light.intensity = std::max({c.r, c.g, c.b});
                light.color = light.intensity > 0.0f ? c / light.intensity : glm::vec3(1.0f);
                light.innerConeAngle = al.mAngleInnerCone;
                light.outerConeAngle = al.mAngleOuterCone;
            }
            if (light.type == LightType::Ambient) continue;
            m_scene.lights.push_back(light);
            m_rig.keepLight(al);
        }
        return true;
    }

    const aiScene& m_ai;
    const std::string& m_path;
    const nlohmann::json& m_doc;
    const SceneOptions& m_options;
    Scene& m_scene;
    const bool m_gltf;
    std::map<std::string, int> m_textureIndex;
    // Textures that could not be read, by key, with the reason; each use of one.
    std::map<std::string, std::string> m_unread;
    struct UnreadTexture {
        size_t material;
        const char* slot;
        std::string why;
    };
    std::vector<UnreadTexture> m_unreadUses;
    int m_missingTexture = -1; // the magenta texture's index, once made
    long long m_zeroNormals = 0;
    const std::set<std::string> m_nodeNames =
        m_gltf ? detail::gltfNames(m_doc, "nodes") : std::set<std::string>{};
    // What a glTF file with animations keeps to be re-posed (scene_rig.h).
    detail::RigLoader m_rig{m_ai, m_path, m_gltf ? m_doc : kNoJson};
    const std::set<std::string> m_meshNames =
        m_gltf ? detail::gltfNames(m_doc, "meshes") : std::set<std::string>{};
};

} // namespace

bool loadScene(const std::string& path, Scene& scene, std::string& error,
               const SceneOptions& options) {
    scene = Scene{};
    if (!std::filesystem::exists(path)) {
        error = path + ": no such file";
        return false;
    }
    Assimp::Importer importer;
    auto* io = new MtlCleaningIOSystem;
    importer.SetIOHandler(io); // the importer owns it
    // A glTF file's JSON, read once for what Assimp 5.2 leaves out of it.
    const nlohmann::json doc =
        isGltf(path) ? detail::gltfJson(path) : nlohmann::json(nlohmann::json::value_t::discarded);
    if (isGltf(path)) {
        std::string flattened;
        if (!detail::gltfFlattenDeepNodes(path, doc, flattened, error)) {
            error = path + ": cannot load the scene: " + error;
            return false;
        }
        // Animations and skins are dhdr's to read (gltfForAssimp).
        if (flattened.empty() && detail::gltfHasAnimationOrSkins(doc))
            flattened = detail::gltfBytesWithJson(path, detail::gltfForAssimp(doc));
        if (!flattened.empty()) io->replace(path, std::move(flattened));
    }
    // ValidateDataStructure turns what would crash later (a face index past the vertices)
    // into an error here.
    // No aiProcess_GenSmoothNormals: a primitive without normals gets flat ones, as glTF
    // requires (SceneBuilder::flatShaded).
    const unsigned flags = aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                           aiProcess_CalcTangentSpace | aiProcess_JoinIdenticalVertices |
                           aiProcess_SortByPType;
    const aiScene* ai = importer.ReadFile(path, flags);
    if (!ai || !ai->mRootNode || (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
        std::string reason = importer.GetErrorString();
        if (reason.empty() && isGltf(path)) reason = detail::gltfEmptySceneReason(doc);
        if (reason.empty())
            reason = ai && !ai->mRootNode ? "the file has no nodes (no scene to render)"
                                          : "the file holds no scene Assimp can use";
        error = path + ": cannot load the scene: " + reason;
        // Assimp's validation refuses some broken glTF cameras (a zfar before the znear) for
        // the whole file: the camera and its fault are named from the file itself.
        if (isGltf(path) && reason.find("aiCamera") != std::string::npos)
            for (const auto& [node, camera] : detail::gltfCamerasByNode(doc))
                if (!camera.problem.empty()) {
                    error = path + ": camera '" + node +
                            "' cannot be rendered from: " + camera.problem +
                            " (Assimp refuses the file: " + reason + ")";
                    break;
                }
        return false;
    }
    if (!SceneBuilder(*ai, path, doc, options, scene).build(error)) return false;
    if (isGltf(path))
        for (const std::string& w : detail::gltfIgnoredFeatures(doc))
            scene.warnings.push_back(w);
    if (scene.meshes.empty()) {
        error = path + ": the scene has no triangles";
        return false;
    }
    return true;
}

void addGroundPlane(Scene& scene, float y) {
    scene.hasGroundPlane = true;
    scene.groundPlaneY = y;
    scene.groundObject = int(scene.objectNames.size());
    scene.objectNames.push_back(kGroundPlaneName);
    Material ground;
    ground.name = kGroundPlaneName;
    ground.baseColor = glm::vec3(0.8f);
    ground.roughness = 1.0f;
    ground.metallic = 0.0f;
    scene.groundMaterial = int(scene.materials.size());
    scene.materials.push_back(ground);
}

glm::dvec3 Scene::boundsMin() const {
    glm::dvec3 lo(std::numeric_limits<double>::infinity());
    for (const Mesh& m : meshes)
        for (const glm::vec3& p : m.positions)
            lo = glm::min(lo, glm::dvec3(p));
    return lo;
}

glm::dvec3 Scene::boundsMax() const {
    glm::dvec3 hi(-std::numeric_limits<double>::infinity());
    for (const Mesh& m : meshes)
        for (const glm::vec3& p : m.positions)
            hi = glm::max(hi, glm::dvec3(p));
    return hi;
}

} // namespace dhdr
