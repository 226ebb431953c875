#include "load/texture_loader.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <assimp/scene.h>
#include <cmath>
#include <dhdr/io/exr_header.h>
#include <filesystem>
#include <memory>
#include <vector>

namespace dhdr::detail {

namespace {

float srgbDecode(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

} // namespace

bool loadTexture(Texture& texture, const std::string& name, const void* data, size_t size,
                 bool srgb, std::string& error) {
    std::unique_ptr<OIIO::Filesystem::IOMemReader> memory;
    OIIO::ImageSpec config;
    if (size > 0) {
        memory = std::make_unique<OIIO::Filesystem::IOMemReader>(data, size);
        OIIO::Filesystem::IOProxy* proxy = memory.get();
        config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    }
    // A texture file's EXR headers are looked at before OpenEXR allocates what they claim,
    // and its size before its pixels are (as every image input of the tools).
    if (size == 0 && !detail::exrHeadersFit(name, error)) {
        error = name + ": cannot read texture: " + error;
        return false;
    }
    // glTF's colours are straight, and the sRGB decode below applies to the colour as stored:
    // OpenImageIO must not premultiply a PNG's colour by its alpha as it reads it.
    config.attribute("oiio:UnassociatedAlpha", 1);
    OIIO::ImageBuf image(name, 0, 0, nullptr, &config);
    if (double(image.spec().width) * double(image.spec().height) > 16384.0 * 16384.0) {
        error = name + ": cannot read texture: " + std::to_string(image.spec().width) + "x" +
                std::to_string(image.spec().height) +
                " is larger than a texture may be "
                "(16384x16384)";
        return false;
    }
    if (!image.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
        error = name + ": cannot read texture: " + image.geterror();
        return false;
    }
    const OIIO::ImageSpec& spec = image.spec();
    // Integer images carry sRGB-encoded values; float images (EXR, HDR) are linear already.
    const OIIO::TypeDesc fileFormat = image.nativespec().format;
    const bool encoded = srgb && (fileFormat.basetype == OIIO::TypeDesc::UINT8 ||
                                  fileFormat.basetype == OIIO::TypeDesc::UINT16);
    texture.name = name;
    texture.width = spec.width;
    texture.height = spec.height;
    texture.rgba.assign(size_t(spec.width) * size_t(spec.height) * 4, 1.0f);
    std::vector<float> pixels(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    image.get_pixels(image.roi(), OIIO::TypeDesc::FLOAT, pixels.data());
    // Grey (+ alpha) images give their grey to R, G and B.
    const int colors = spec.nchannels >= 3 ? 3 : 1;
    for (size_t i = 0; i < size_t(spec.width) * size_t(spec.height); ++i) {
        const float* p = &pixels[i * size_t(spec.nchannels)];
        float* q = &texture.rgba[i * 4];
        for (int c = 0; c < 3; ++c) {
            const float v = p[std::min(c, colors - 1)];
            q[c] = encoded ? srgbDecode(v) : v;
        }
        if (spec.nchannels == 4 || spec.nchannels == 2) q[3] = p[spec.nchannels - 1];
    }
    return true;
}

int TextureTable::load(const std::string& ref, bool srgb, const char* slot) {
    // The same file can be a colour (sRGB) and a data texture: one decoding of each.
    const std::string key = (srgb ? "srgb:" : "data:") + ref;
    if (auto it = m_unread.find(key); it != m_unread.end()) return unread(it->second, slot);
    if (auto it = m_index.find(key); it != m_index.end()) return it->second;
    std::string why;
    int index = -1;
    if (!decode(ref, srgb, index, why)) {
        m_unread[key] = why;
        return unread(why, slot);
    }
    m_index[key] = index;
    return index;
}

// Records an unread texture of the material being loaded; the index to use in its place:
// the magenta one for colours, none for a normal map.
int TextureTable::unread(const std::string& why, const char* slot) {
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

bool TextureTable::report(bool strict, std::string& error) {
    for (const UnreadTexture& u : m_unreadUses) {
        const std::string material = m_scene.materials[u.material].name;
        const std::string what = "material '" + material + "', " + u.slot + " texture: " + u.why;
        if (strict) {
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

bool TextureTable::decode(const std::string& ref, bool srgb, int& index, std::string& error) {
    Texture texture;
    if (const aiTexture* embedded = m_ai.GetEmbeddedTexture(ref.c_str())) {
        if (embedded->mHeight != 0) {
            error = ref + ": uncompressed embedded textures are not supported";
            return false;
        }
        const std::string hint = std::string("embedded.") + embedded->achFormatHint;
        if (!loadTexture(texture, hint, embedded->pcData, embedded->mWidth, srgb, error))
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
        if (!loadTexture(texture, file.string(), nullptr, 0, srgb, error)) return false;
    }
    index = int(m_scene.textures.size());
    m_scene.textures.push_back(std::move(texture));
    return true;
}

} // namespace dhdr::detail
