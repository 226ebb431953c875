#include "load/camera_light_reader.h"
#include "load/gltf_json.h"
#include "load/material_reader.h"
#include "load/mesh_reader.h"
#include "load/rig_loader.h"
#include "load/texture_loader.h"

#include <algorithm>
#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cstdio>
#include <cstring>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_info.h>
#include <filesystem>
#include <fstream>
#include <limits>
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

// Blender's naming of datablocks, so that Cryptomatte manifests and the G-buffer's name
// tables hold no empty name and no name twice: a name the file gives keeps it at its
// first use; an unnamed object or material is "Object" or "Material", and a name already
// taken gets the first free ".001", ".002"... suffix ("Object.001", "box.001").
void blenderNames(std::vector<std::string*> names, const std::string& fallback) {
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

void nameUnnamed(Scene& scene) {
    std::vector<std::string*> objects, materials;
    for (std::string& name : scene.objectNames)
        objects.push_back(&name);
    for (Material& m : scene.materials)
        materials.push_back(&m.name);
    blenderNames(objects, "Object");
    blenderNames(materials, "Material");
}

// Builds a Scene from Assimp's: the materials, then the node tree walked for its meshes, then
// the cameras and lights, each by its reader (material_reader.h, mesh_reader.h,
// camera_light_reader.h); the names completed and the rig finished here.
class SceneBuilder {
public:
    // `doc`: the glTF file's JSON (gltfJson), discarded for other files.
    SceneBuilder(const aiScene& ai, const std::string& path, const nlohmann::json& doc,
                 const SceneOptions& options, Scene& scene)
        : m_ai(ai), m_path(path), m_doc(doc), m_options(options), m_scene(scene),
          m_gltf(isGltf(path)) {}

    bool build(std::string& error) {
        detail::readMaterials(m_ai, m_doc, m_gltf, m_textures, m_scene);
        if (m_gltf) readMaterialExtensions();
        if (!m_rig.error().empty()) {
            error = m_rig.error();
            return false;
        }
        if (!visitAll(error)) return false;
        nameUnnamed(m_scene);
        if (!m_textures.report(m_options.strict, error)) return false;
        if (m_meshes.zeroNormals() > 0)
            m_scene.warnings.push_back(
                std::to_string(m_meshes.zeroNormals()) +
                " vertex normals in the file have zero length; their triangles are shaded with "
                "the geometric normal");
        const detail::NodeWorld world = [this](const aiString& name) { return nodeWorld(name); };
        detail::readCameras(m_ai, m_doc, m_gltf, world, m_scene, m_rig);
        if (!detail::readLights(m_ai, m_path, m_doc, m_gltf, world, m_scene, m_rig, error))
            return false;
        if (m_rig.active()) m_scene.rig = m_rig.finish();
        return true;
    }

private:
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

    // The extensions each glTF material names, matched by name as readMaterials matches what
    // else Assimp leaves out (the names are still the file's: nameUnnamed comes later).
    void readMaterialExtensions() {
        const auto byName = detail::gltfMaterialExtensions(m_doc);
        for (size_t i = 0; i < m_scene.materials.size(); ++i) {
            const auto it = byName.find(m_scene.materials[i].name);
            if (it == byName.end()) continue;
            for (const std::string& name : it->second)
                m_scene.materialExtensions[int(i)].push_back(
                    {name, detail::gltfExtensionRendered(m_doc, name)});
        }
    }

    // Each node with meshes becomes an object; its meshes go to the mesh reader.
    bool visitAll(std::string& error) {
        bool ok = true;
        forEachNode([&](const aiNode& node, const glm::dmat4& world) {
            if (node.mNumMeshes == 0) return ok;
            const int object = int(m_scene.objectNames.size());
            // Unnamed: the mesh's name, else a generated one (nameUnnamed).
            std::string name = shownName(node.mName.C_Str(), m_nodeNames, "nodes");
            if (name.empty())
                name =
                    shownName(m_ai.mMeshes[node.mMeshes[0]]->mName.C_Str(), m_meshNames, "meshes");
            m_scene.objectNames.push_back(name);
            const glm::dmat3 normalMatrix = normalMatrixOf(world);
            for (unsigned i = 0; i < node.mNumMeshes && ok; ++i)
                ok = m_meshes.add(*m_ai.mMeshes[node.mMeshes[i]], node, i, world, normalMatrix,
                                  object, error);
            return ok;
        });
        return ok;
    }

    // A name as the file gives it: empty for one Assimp made up for an unnamed glTF element
    // ("nodes[3]", "meshes[0]"), unless the file itself uses that name.
    std::string shownName(const std::string& name, const std::set<std::string>& given,
                          const std::string& array) const {
        if (!m_gltf || given.count(name) || name.rfind(array + "[", 0) != 0) return name;
        return {};
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

    const aiScene& m_ai;
    const std::string& m_path;
    const nlohmann::json& m_doc;
    const SceneOptions& m_options;
    Scene& m_scene;
    const bool m_gltf;
    const std::set<std::string> m_nodeNames =
        m_gltf ? detail::gltfNames(m_doc, "nodes") : std::set<std::string>{};
    // What a glTF file with animations keeps to be re-posed (scene_rig.h).
    detail::RigLoader m_rig{m_ai, m_path, m_gltf ? m_doc : kNoJson};
    const std::set<std::string> m_meshNames =
        m_gltf ? detail::gltfNames(m_doc, "meshes") : std::set<std::string>{};
    detail::TextureTable m_textures{m_ai, m_path, m_scene};
    detail::MeshReader m_meshes{
        m_path, m_scene, m_rig, {m_gltf, m_gltf&& detail::gltfHasRgbVertexColors(m_doc)}};
};

// Hands Assimp a glTF file whose deep node tree dhdr flattened (gltfFlattenDeepNodes), or
// without its animations and skins, which are dhdr's to read (gltfForAssimp).
bool prepareGltf(const std::string& path, const nlohmann::json& doc, MtlCleaningIOSystem& io,
                 std::string& error) {
    std::string flattened;
    if (!detail::gltfFlattenDeepNodes(path, doc, flattened, error)) {
        error = path + ": cannot load the scene: " + error;
        return false;
    }
    if (flattened.empty() && detail::gltfHasAnimationOrSkins(doc))
        flattened = detail::gltfBytesWithJson(path, detail::gltfForAssimp(doc));
    if (!flattened.empty()) io.replace(path, std::move(flattened));
    return true;
}

// Why Assimp could not import the file at `path` (`ai`, perhaps null).
std::string importError(const std::string& path, const nlohmann::json& doc, const aiScene* ai,
                        const Assimp::Importer& importer) {
    std::string reason = importer.GetErrorString();
    if (reason.empty() && isGltf(path)) reason = detail::gltfEmptySceneReason(doc);
    if (reason.empty())
        reason = ai && !ai->mRootNode ? "the file has no nodes (no scene to render)"
                                      : "the file holds no scene Assimp can use";
    // Assimp's validation refuses some broken glTF cameras (a zfar before the znear) for
    // the whole file: the camera and its fault are named from the file itself.
    if (isGltf(path) && reason.find("aiCamera") != std::string::npos)
        for (const auto& [node, camera] : detail::gltfCamerasByNode(doc))
            if (!camera.problem.empty())
                return path + ": camera '" + node + "' cannot be rendered from: " + camera.problem +
                       " (Assimp refuses the file: " + reason + ")";
    if (const std::string draco = isGltf(path) ? detail::gltfDracoIndexProblem(doc) : "";
        !draco.empty())
        return path + ": cannot load the scene: " + draco + " (Assimp: " + reason + ")";
    return path + ": cannot load the scene: " + reason;
}

// Assimp reads the animations of Collada, FBX and other formats and drops glTF 1.0's; dhdr
// plays glTF 2.0's only, and says so rather than render a still frame without a word.
void warnUnplayedAnimations(const aiScene& ai, const std::string& path, const nlohmann::json& doc,
                            Scene& scene) {
    const size_t n = isGltf(path) ? detail::gltfUnplayedAnimations(doc) : ai.mNumAnimations;
    if (n == 0) return;
    scene.warnings.push_back(
        "the file's " + std::to_string(n) + (n == 1 ? " animation is" : " animations are") +
        " not played: dhdr plays glTF 2.0 animations only, and renders this scene still, as its "
        "nodes stand in the file");
}

// A material in use that hides every surface it covers is named: without it, its objects
// vanish and the tools say only that no surface is in view.
void warnInvisibleMaterials(Scene& scene) {
    for (const int i : materialsInUse(scene)) {
        const Material& m = scene.materials[size_t(i)];
        std::string why;
        char numbers[96];
        if (m.alphaMode == AlphaMode::Blend && !(m.alpha > 0.0f)) {
            why = "has opacity 0";
        } else if (m.alphaMode == AlphaMode::Mask && !(m.alpha >= m.alphaCutoff)) {
            // Texture alpha only lowers the factor's: every point is below the cutoff.
            std::snprintf(numbers, sizeof numbers, "%g is below its alphaCutoff %g", m.alpha,
                          m.alphaCutoff);
            why = std::string("is cut out everywhere: its alpha ") + numbers;
        } else {
            continue;
        }
        std::vector<std::string> objects;
        for (const Mesh& mesh : scene.meshes) {
            const std::string& name = scene.objectNames[size_t(mesh.object)];
            if (mesh.material == i &&
                std::find(objects.begin(), objects.end(), name) == objects.end())
                objects.push_back(name);
        }
        std::string named;
        for (size_t k = 0; k < objects.size() && k < 3; ++k)
            named += (k ? ", " : "") + objects[k];
        if (objects.size() > 3) named += " and " + std::to_string(objects.size() - 3) + " more";
        scene.warnings.push_back("material '" + m.name + "' " + why +
                                 ": the surfaces that use it are invisible (" + named +
                                 "); if it is meant to be seen, set its opacity or alpha in the "
                                 "file");
    }
}

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
    if (isGltf(path) && !prepareGltf(path, doc, *io, error)) return false;
    // ValidateDataStructure turns what would crash later (a face index past the vertices)
    // into an error here.
    // No aiProcess_GenSmoothNormals: a primitive without normals gets flat ones, as glTF
    // requires (mesh_reader.cpp, flatShaded).
    const unsigned flags = aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                           aiProcess_CalcTangentSpace | aiProcess_JoinIdenticalVertices |
                           aiProcess_SortByPType;
    const aiScene* ai = importer.ReadFile(path, flags);
    if (!ai || !ai->mRootNode || (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
        error = importError(path, doc, ai, importer);
        return false;
    }
    if (!SceneBuilder(*ai, path, doc, options, scene).build(error)) return false;
    if (isGltf(path))
        for (const std::string& w : detail::gltfIgnoredFeatures(doc))
            scene.warnings.push_back(w);
    warnUnplayedAnimations(*ai, path, doc, scene);
    warnInvisibleMaterials(scene);
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
