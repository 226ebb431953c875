#include "load/texture_loader.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <assimp/scene.h>
#include <cmath>
#include <cstring>
#include <dhdr/io/exr_header.h>
#include <filesystem>
#include <limits>
#include <memory>
#include <type_traits>
#include <vector>

namespace dhdr::detail {

namespace {

float srgbDecode(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

// Each code of an 8- or 16-bit type as OpenImageIO converts it to float, and that decoded from
// sRGB: the values a texture converted to float whole would hold.
struct DecodeTables {
    std::shared_ptr<const std::vector<float>> linear, srgb;
};

const DecodeTables& decodeTables(OIIO::TypeDesc type) {
    static const auto make = [](OIIO::TypeDesc t) {
        const size_t n = t == OIIO::TypeDesc::UINT8 ? 256 : 65536;
        std::vector<std::uint16_t> wide(n);
        std::vector<std::uint8_t> narrow(n);
        for (size_t i = 0; i < n; ++i) {
            wide[i] = std::uint16_t(i);
            narrow[i] = std::uint8_t(i);
        }
        auto linear = std::make_shared<std::vector<float>>(n);
        const void* codes = t == OIIO::TypeDesc::UINT8 ? static_cast<const void*>(narrow.data())
                                                       : static_cast<const void*>(wide.data());
        OIIO::convert_pixel_values(t, codes, OIIO::TypeDesc::FLOAT, linear->data(), int(n));
        auto srgb = std::make_shared<std::vector<float>>(n);
        for (size_t i = 0; i < n; ++i)
            (*srgb)[i] = srgbDecode((*linear)[i]);
        return DecodeTables{linear, srgb};
    };
    static const DecodeTables eight = make(OIIO::TypeDesc::UINT8);
    static const DecodeTables sixteen = make(OIIO::TypeDesc::UINT16);
    return type == OIIO::TypeDesc::UINT8 ? eight : sixteen;
}

// The image's texels as RGBA of type T: grey (+ alpha) gives its grey to R, G and B; without
// alpha, alpha is the type's 1.
template <class T>
std::vector<T> rgbaOf(const OIIO::ImageBuf& image) {
    const OIIO::ImageSpec& spec = image.spec();
    const size_t texels = size_t(spec.width) * size_t(spec.height);
    const T one = std::is_floating_point_v<T> ? T(1) : std::numeric_limits<T>::max();
    std::vector<T> out(texels * 4, one);
    const T* p = static_cast<const T*>(image.localpixels());
    const int nch = spec.nchannels;
    const int colors = nch >= 3 ? 3 : 1;
    for (size_t i = 0; i < texels; ++i, p += nch) {
        T* q = &out[i * 4];
        for (int c = 0; c < 3; ++c)
            q[c] = p[std::min(c, colors - 1)];
        if (nch == 4 || nch == 2) q[3] = p[nch - 1];
    }
    return out;
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
    // Integer images carry sRGB-encoded values; float images (EXR, HDR) are linear already.
    const OIIO::TypeDesc::BASETYPE base = OIIO::TypeDesc::BASETYPE(image.spec().format.basetype);
    const bool codes = base == OIIO::TypeDesc::UINT8 || base == OIIO::TypeDesc::UINT16;
    const OIIO::TypeDesc held = base == OIIO::TypeDesc::UINT8    ? OIIO::TypeDesc::UINT8
                                : base == OIIO::TypeDesc::UINT16 ? OIIO::TypeDesc::UINT16
                                                                 : OIIO::TypeDesc::FLOAT;
    if (!image.read(0, 0, true, held)) {
        error = name + ": cannot read texture: " + image.geterror();
        return false;
    }
    texture.name = name;
    texture.width = image.spec().width;
    texture.height = image.spec().height;
    if (held == OIIO::TypeDesc::UINT8) {
        texture.codes8 = rgbaOf<std::uint8_t>(image);
    } else if (held == OIIO::TypeDesc::UINT16) {
        texture.codes16 = rgbaOf<std::uint16_t>(image);
    } else {
        texture.rgba = rgbaOf<float>(image);
    }
    if (codes) {
        const DecodeTables& tables = decodeTables(held);
        texture.colorTable = srgb ? tables.srgb : tables.linear;
        texture.alphaTable = tables.linear;
    }
    buildMipmaps(texture);
    if (!srgb) texture.normalLength = meanNormalLength(texture);
    return true;
}

int TextureTable::load(const std::string& ref, bool srgb, const char* slot) {
    // The same file can be a colour (sRGB) and a data texture: one decoding of each.
    return cached((srgb ? "srgb:" : "data:") + ref, slot, [&](Texture& texture, std::string& why) {
        return decode(ref, srgb, texture, why);
    });
}

int TextureTable::cached(const std::string& key, const char* slot,
                         const std::function<bool(Texture&, std::string&)>& decode) {
    if (auto it = m_unread.find(key); it != m_unread.end()) return unread(it->second, slot);
    if (auto it = m_index.find(key); it != m_index.end()) return it->second;
    Texture texture;
    std::string why;
    if (!decode(texture, why)) {
        m_unread[key] = why;
        return unread(why, slot);
    }
    const int index = int(m_scene.textures.size());
    m_scene.textures.push_back(std::move(texture));
    m_index[key] = index;
    return index;
}

int TextureTable::loadGltfImage(const nlohmann::json& doc, size_t image, bool srgb,
                                const char* slot) {
    const nlohmann::json* images =
        doc.is_object() && doc.contains("images") ? &doc["images"] : nullptr;
    if (!images || !images->is_array() || image >= images->size() || !(*images)[image].is_object())
        return unread("image " + std::to_string(image) + " does not exist", slot);
    const nlohmann::json& entry = (*images)[image];
    if (entry.contains("uri") && entry["uri"].is_string() &&
        entry["uri"].get<std::string>().rfind("data:", 0) != 0)
        return load(entry["uri"].get<std::string>(), srgb, slot);
    if (!m_buffers) m_buffers = std::make_unique<GltfBuffers>(m_path, doc);
    // An image Assimp holds too (its "*k", when another slot of the file names it) is the one
    // texture: found by its bytes, once per image.
    auto known = m_embeddedNames.find(image);
    if (known == m_embeddedNames.end()) {
        std::vector<std::uint8_t> bytes;
        std::string name = "images[" + std::to_string(image) + "]", why;
        if (m_buffers->readImage(image, bytes, why))
            for (unsigned k = 0; k < m_ai.mNumTextures; ++k) {
                const aiTexture& t = *m_ai.mTextures[k];
                if (t.mHeight == 0 && t.mWidth == bytes.size() &&
                    std::memcmp(t.pcData, bytes.data(), bytes.size()) == 0) {
                    name = "*" + std::to_string(k);
                    break;
                }
            }
        known = m_embeddedNames.emplace(image, name).first;
    }
    const std::string& name = known->second;
    if (name[0] == '*') return load(name, srgb, slot);
    return cached((srgb ? "srgb:" : "data:") + name, slot, [&](Texture& texture, std::string& why) {
        std::vector<std::uint8_t> bytes;
        if (!m_buffers->readImage(image, bytes, why)) return false;
        // OpenImageIO picks the decoder by the name's extension: the mimeType's,
        // else the bytes' signature (glTF allows PNG and JPEG).
        const std::string mime = entry.contains("mimeType") && entry["mimeType"].is_string()
                                     ? entry["mimeType"].get<std::string>()
                                     : "";
        const bool jpeg = mime == "image/jpeg" || (mime.empty() && bytes.size() > 2 &&
                                                   bytes[0] == 0xff && bytes[1] == 0xd8);
        if (!loadTexture(texture, jpeg ? "embedded.jpg" : "embedded.png", bytes.data(),
                         bytes.size(), srgb, why)) {
            why = name + ": " + why;
            return false;
        }
        texture.name = name;
        return true;
    });
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

bool TextureTable::decode(const std::string& ref, bool srgb, Texture& texture, std::string& error) {
    if (const aiTexture* embedded = m_ai.GetEmbeddedTexture(ref.c_str())) {
        if (embedded->mHeight != 0) {
            error = ref + ": uncompressed embedded textures are not supported";
            return false;
        }
        const std::string hint = std::string("embedded.") + embedded->achFormatHint;
        if (!loadTexture(texture, hint, embedded->pcData, embedded->mWidth, srgb, error))
            return false;
        texture.name = ref;
        return true;
    }
    auto file = std::filesystem::path(m_path).parent_path() / ref;
    // Files written on Windows name textures with backslashes (".\\wall.jpg").
    if (std::string unix = ref;
        !std::filesystem::exists(file) && unix.find('\\') != std::string::npos) {
        std::replace(unix.begin(), unix.end(), '\\', '/');
        file = std::filesystem::path(m_path).parent_path() / unix;
    }
    return loadTexture(texture, file.string(), nullptr, 0, srgb, error);
}

} // namespace dhdr::detail
