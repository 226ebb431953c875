// Loading textures: decoding through OpenImageIO, and the scene's table of them (each
// referenced file decoded once, embedded or beside the scene file; magenta for an unread one).
#pragma once

#include "load/gltf_buffers.h"

#include <dhdr/deferred/scene/scene.h>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

struct aiScene;

namespace dhdr::detail {

// Reads an image file (or, with `size` > 0, encoded bytes in memory, e.g. a PNG inside a .glb)
// into RGBA floats. With `srgb` (glTF's base colour and emissive textures), 8- and 16-bit
// images are taken as sRGB-encoded and decoded to linear; without (normal and
// metallic-roughness maps), their values are kept as they are.
bool loadTexture(Texture& texture, const std::string& name, const void* data, size_t size,
                 bool srgb, std::string& error);

// The textures of a scene being loaded (`ai`, from the file at `path`), in Scene::textures.
//
// A texture that cannot be read (missing, undecodable) does not stop the render: the
// material shows magenta (1, 0, 1) times its factor there, as Blender shows a missing
// texture in pink, and a normal map is left out; report() warns, naming the file and the
// material, or with SceneOptions::strict fails.
class TextureTable {
public:
    TextureTable(const aiScene& ai, const std::string& path, Scene& scene)
        : m_ai(ai), m_path(path), m_scene(scene) {}

    // The texture `ref` of the material being read (the next in Scene::materials) for its
    // `slot` ("base colour", "emissive", "normal"): its index in Scene::textures, or −1.
    int load(const std::string& ref, bool srgb, const char* slot);

    // The same for image `image` of the glTF file whose JSON is `doc`, for the slots Assimp 5.2
    // does not report (KHR_materials_specular's): an image that names a file by its uri is
    // load()ed by that name, as Assimp names it; one the file holds itself (a bufferView, a data
    // URI) is decoded from its bytes, once (Assimp's own decoding when it holds the same bytes).
    int loadGltfImage(const nlohmann::json& doc, size_t image, bool srgb, const char* slot);

    // A texture reference of the material being read that leads to no image (`why`): reported
    // as an unread texture is; the index to use in its place.
    int unreadable(const std::string& why, const char* slot) { return unread(why, slot); }

    // After the materials have their names: one warning per unread texture use, naming the
    // texture (OpenImageIO's message names the file) and the material; with `strict`, false
    // with `error`.
    bool report(bool strict, std::string& error);

private:
    int unread(const std::string& why, const char* slot);
    // The texture of `key` ("srgb:" or "data:" and a name), decoded by `decode` the first time.
    int cached(const std::string& key, const char* slot,
               const std::function<bool(Texture&, std::string&)>& decode);
    bool decode(const std::string& ref, bool srgb, Texture& texture, std::string& error);

    const aiScene& m_ai;
    const std::string& m_path;
    Scene& m_scene;
    std::map<std::string, int> m_index;
    // Textures that could not be read, by key, with the reason; each use of one.
    std::map<std::string, std::string> m_unread;
    struct UnreadTexture {
        size_t material;
        const char* slot;
        std::string why;
    };
    std::vector<UnreadTexture> m_unreadUses;
    int m_missingTexture = -1;              // the magenta texture's index, once made
    std::unique_ptr<GltfBuffers> m_buffers; // the glTF file's, once an image needs them
    // Images the glTF file holds itself, by index: the name of their texture ("*k" when Assimp
    // holds the same bytes, else "images[N]").
    std::map<size_t, std::string> m_embeddedNames;
};

} // namespace dhdr::detail
