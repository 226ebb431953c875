#include <ImfIDManifest.h>
#include <OpenImageIO/imageio.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/io/errors.h>
#include <dhdr/io/exr_header.h>
#include <dhdr/io/pixel_limit.h>
#include <filesystem>
#include <memory>
#include <utility>

namespace dhdr::gbuffer {

namespace {

std::vector<std::string> namesOf(bool deep, unsigned uses) {
    std::vector<std::string> names;
    for (const ContractChannel& c : kContract)
        if ((deep || c.need != Need::DeepOnly) && (c.use == 0 || (c.use & uses)))
            for (int i = 0; i < c.components; ++i)
                names.push_back(c.names[i]);
    return names;
}

} // namespace

float cryptomatteId(const std::string& name, std::uint32_t* hash) {
    // OpenEXR's MurmurHash3_x86_32 with seed 0, the hash Cryptomatte names.
    std::uint32_t h = Imf::IDManifest::MurmurHash32(name);
    if (hash) *hash = h;
    const std::uint32_t exponent = (h >> 23) & 255u;
    if (exponent == 0 || exponent == 255) h ^= 1u << 23;
    float f;
    std::memcpy(&f, &h, sizeof f);
    return f;
}

void writeCryptomatteHeader(OIIO::ImageSpec& spec, const std::string& layer,
                            const std::vector<std::string>& names) {
    std::uint32_t layerHash = 0;
    cryptomatteId(layer, &layerHash);
    char key[16];
    std::snprintf(key, sizeof key, "%08x", layerHash);
    const std::string prefix = "cryptomatte/" + std::string(key, 7) + "/";
    std::string manifest = "{";
    for (size_t i = 0; i < names.size(); ++i) {
        std::uint32_t h = 0;
        cryptomatteId(names[i], &h);
        char hex[16];
        std::snprintf(hex, sizeof hex, "%08x", h);
        std::string quoted;
        for (const char c : names[i]) {
            if (static_cast<unsigned char>(c) < 0x20) { // a control character: JSON's \u form
                char escaped[8];
                std::snprintf(escaped, sizeof escaped, "\\u%04x", unsigned(c));
                quoted += escaped;
                continue;
            }
            if (c == '"' || c == '\\') quoted += '\\';
            quoted += c;
        }
        manifest += (i ? ",\"" : "\"") + quoted + "\":\"" + hex + "\"";
    }
    manifest += "}";
    spec.attribute(prefix + "name", layer);
    spec.attribute(prefix + "hash", "MurmurHash3_32");
    spec.attribute(prefix + "conversion", "uint32_to_float32");
    spec.attribute(prefix + "manifest", manifest);
}

std::vector<std::string> channelNames(unsigned uses) {
    return namesOf(false, uses);
}

std::vector<std::string> deepChannelNames(unsigned uses) {
    return namesOf(true, uses);
}

bool isWrittenLayout(const std::vector<std::string>& names, bool deep) {
    for (unsigned uses = 0; uses <= kAllUses; ++uses) {
        std::vector<std::string> written = namesOf(deep, uses);
        if (names == written) return true;
        written.insert(written.end(), std::begin(kMotion), std::end(kMotion));
        if (names == written) return true;
    }
    return false;
}

std::vector<OIIO::TypeDesc> channelFormats(const std::vector<std::string>& names) {
    std::vector<OIIO::TypeDesc> formats;
    for (const std::string& name : names) {
        OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT;
        for (const ContractChannel& c : kContract)
            for (int i = 0; i < c.components; ++i)
                if (name == c.names[i])
                    type = c.type == FileType::Float  ? OIIO::TypeDesc::FLOAT
                           : c.type == FileType::Uint ? OIIO::TypeDesc::UINT
                                                      : OIIO::TypeDesc::HALF;
        formats.push_back(type);
    }
    return formats;
}

namespace {

// Index of the first of `names` in `spec`, checking that the others follow it.
bool findGroup(const OIIO::ImageSpec& spec, const char* const* names, int count, int& index,
               std::string& missing) {
    index = spec.channelindex(names[0]);
    for (int i = 0; i < count; ++i) {
        if (index < 0 || spec.channelindex(names[i]) != index + i) {
            missing = spec.channelindex(names[i]) < 0 ? names[i]
                                                      : std::string(names[i]) + " (out of order)";
            index = -1;
            return false;
        }
    }
    return true;
}

} // namespace

bool findLayout(const OIIO::ImageSpec& spec, Layout& layout, std::string& missing) {
    layout = Layout{};
    for (const ContractChannel& c : kContract) {
        if (c.need == Need::Required) {
            if (!findGroup(spec, c.names, c.components, layout.*c.field, missing)) return false;
        } else {
            std::string ignored;
            findGroup(spec, c.names, c.components, layout.*c.field, ignored);
        }
    }
    return true;
}

int findGBufferPart(const std::string& path, std::string& error) {
    if (!detail::exrHeadersFit(path, error)) return -1;
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
    if (!in) {
        error = OIIO::geterror();
        return -1;
    }
    std::string firstMissing;
    for (int s = 0; in->seek_subimage(s, 0); ++s) {
        const OIIO::ImageSpec& spec = in->spec();
        Layout layout;
        std::string missing;
        if (!findLayout(spec, layout, missing)) {
            if (s == 0) firstMissing = missing;
            continue;
        }
        // Real-valued channels must be stored as half or float (a normal stored as uint
        // would clamp); ids as uint, or half/float.
        for (const ContractChannel& entry : kContract)
            for (int i = 0; i < entry.components; ++i) {
                const int c = spec.channelindex(entry.names[i]);
                if (c < 0) continue;
                const OIIO::TypeDesc type = spec.channelformat(c);
                const bool real = type == OIIO::TypeDesc::HALF || type == OIIO::TypeDesc::FLOAT;
                if (real || (entry.type == FileType::Uint && type == OIIO::TypeDesc::UINT))
                    continue;
                error = std::string("channel '") + entry.names[i] + "' is stored as " +
                        type.c_str() + "; the G-buffer contract stores it as " +
                        (entry.type == FileType::Uint ? "uint" : "half or float");
                return -1;
            }
        return s;
    }
    error = "no channel '" + firstMissing + "' — is this a G-buffer?";
    return -1;
}

bool probeGBufferFile(const std::string& path, int& part, bool& deep, std::string& error) {
    deep = false;
    if (!std::filesystem::exists(path)) {
        error = path + ": no such file";
        return false;
    }
    part = findGBufferPart(path, error);
    if (part < 0) {
        error = error.find("G-buffer") != std::string::npos ? path + ": " + error
                                                            : cannotRead(path, error);
        return false;
    }
    if (auto probe = OIIO::ImageInput::open(path); probe && probe->seek_subimage(part, 0)) {
        deep = probe->spec().deep;
        const OIIO::ImageSpec& s = probe->spec();
        if (const std::string e = pixelLimitError(s.width, s.height, s.depth); !e.empty()) {
            error = path + ": " + e;
            return false;
        }
    }
    return true;
}

namespace {

bool getMatrix(const OIIO::ImageSpec& spec, const char* name, glm::dmat4& m) {
    const OIIO::ParamValue* p = spec.find_attribute(name, OIIO::TypeMatrix44);
    if (!p) return false;
    // OpenEXR's M44f is row-major for row vectors; read as glm's column-major for column
    // vectors, the same 16 numbers are the same transform.
    const float* f = static_cast<const float*>(p->data());
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            m[c][r] = f[4 * c + r];
    return true;
}

void setMatrix(OIIO::ImageSpec& spec, const char* name, const glm::dmat4& m) {
    float f[16];
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            f[4 * c + r] = float(m[c][r]);
    spec.attribute(name, OIIO::TypeMatrix44, f);
}

} // namespace

bool readCamera(const OIIO::ImageSpec& spec, CameraInfo& camera, std::string& error) {
    camera = CameraInfo{};
    if (!getMatrix(spec, "worldToCamera", camera.worldToCamera) ||
        !getMatrix(spec, "worldToNDC", camera.worldToNDC)) {
        error = "no worldToCamera/worldToNDC attributes — is this a G-buffer?";
        return false;
    }
    auto usable = [](const glm::dmat4& m) {
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(m[c][r])) return false;
        const double det = glm::determinant(m);
        return std::isfinite(det) && std::abs(det) > 1e-30;
    };
    for (const auto& [name, m] :
         {std::pair<const char*, const glm::dmat4&>{"worldToCamera", camera.worldToCamera},
          {"worldToNDC", camera.worldToNDC}}) {
        if (!usable(m)) {
            error = std::string("the header's ") + name +
                    " is not a usable camera matrix (zero, not finite or not invertible)";
            return false;
        }
    }
    const glm::dmat4 cameraToWorld = glm::inverse(camera.worldToCamera);
    camera.position = glm::dvec3(cameraToWorld[3]);
    camera.forward = glm::normalize(glm::dvec3(cameraToWorld * glm::dvec4(0.0, 0.0, -1.0, 0.0)));
    const glm::dmat4 cameraToNDC = camera.worldToNDC * cameraToWorld;
    // Row 3 of a projection: (0 0 −1 0) perspective, (0 0 0 1) orthographic.
    camera.orthographic = std::abs(cameraToNDC[2][3]) < 1e-6 * std::abs(cameraToNDC[3][3]);
    return true;
}

void writeCamera(OIIO::ImageSpec& spec, const CameraInfo& camera) {
    setMatrix(spec, "worldToCamera", camera.worldToCamera);
    setMatrix(spec, "worldToNDC", camera.worldToNDC);
}

} // namespace dhdr::gbuffer
