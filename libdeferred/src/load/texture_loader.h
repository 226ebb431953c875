// Loading textures: decoding through OpenImageIO, and the scene's table of them (each
// referenced file decoded once, embedded or beside the scene file; magenta for an unread one).
#pragma once

#include <dhdr/deferred/scene/scene.h>
#include <map>
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

    // After the materials have their names: one warning per unread texture use, naming the
    // texture (OpenImageIO's message names the file) and the material; with `strict`, false
    // with `error`.
    bool report(bool strict, std::string& error);

private:
    int unread(const std::string& why, const char* slot);
    bool decode(const std::string& ref, bool srgb, int& index, std::string& error);

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
    int m_missingTexture = -1; // the magenta texture's index, once made
};

} // namespace dhdr::detail
