#include "load/gltf_buffers.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <tuple>

namespace dhdr::detail {

namespace {

std::vector<std::uint8_t> fromBase64(const std::string& text, size_t from, bool& ok) {
    std::vector<std::uint8_t> out;
    std::uint32_t bits = 0;
    int nbits = 0;
    ok = true;
    for (size_t i = from; i < text.size(); ++i) {
        const char c = text[i];
        int v = -1;
        if (c >= 'A' && c <= 'Z')
            v = c - 'A';
        else if (c >= 'a' && c <= 'z')
            v = c - 'a' + 26;
        else if (c >= '0' && c <= '9')
            v = c - '0' + 52;
        else if (c == '+' || c == '-')
            v = 62;
        else if (c == '/' || c == '_')
            v = 63;
        else if (c == '=' || c == '\n' || c == '\r')
            continue;
        else {
            ok = false;
            return out;
        }
        bits = (bits << 6) | std::uint32_t(v);
        nbits += 6;
        if (nbits >= 8) {
            nbits -= 8;
            out.push_back(std::uint8_t((bits >> nbits) & 0xffu));
        }
    }
    return out;
}

// A URI's %XX escapes decoded (file names with spaces are written as %20).
std::string percentDecoded(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uri[i + 1]) &&
            std::isxdigit(uri[i + 2])) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// The BIN chunk of a .glb: the chunk after the JSON one.
bool glbBinChunk(const std::string& path, std::vector<std::uint8_t>& out) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0) return false;
    std::uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, bytes.data() + 12, 4);
    const size_t at = 20 + size_t(jsonLength);
    if (at + 8 > bytes.size()) return false;
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + at, 4);
    if (std::memcmp(bytes.data() + at + 4, "BIN\0", 4) != 0 || at + 8 + length > bytes.size())
        return false;
    out.assign(bytes.begin() + long(at + 8), bytes.begin() + long(at + 8 + length));
    return true;
}

size_t componentSize(int type) {
    switch (type) {
    case 5120:
    case 5121:
        return 1;
    case 5122:
    case 5123:
        return 2;
    case 5125:
    case 5126:
        return 4;
    default:
        return 0;
    }
}

// One component as glTF 2.0 §3.11 maps it.
float component(const std::uint8_t* p, int type, bool normalized) {
    switch (type) {
    case 5126: {
        float f;
        std::memcpy(&f, p, 4);
        return f;
    }
    case 5120: {
        const auto v = std::int8_t(*p);
        return normalized ? std::max(float(v) / 127.0f, -1.0f) : float(v);
    }
    case 5121:
        return normalized ? float(*p) / 255.0f : float(*p);
    case 5122: {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
    }
    case 5123: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? float(v) / 65535.0f : float(v);
    }
    default: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return float(v);
    }
    }
}

bool unsignedField(const nlohmann::json& j, const char* key, size_t& out) {
    if (!j.contains(key) || !j[key].is_number_unsigned()) return false;
    out = j[key].get<size_t>();
    return true;
}

} // namespace

int gltfComponents(const std::string& type) {
    if (type == "SCALAR") return 1;
    if (type == "VEC2") return 2;
    if (type == "VEC3") return 3;
    if (type == "VEC4" || type == "MAT2") return 4;
    if (type == "MAT3") return 9;
    if (type == "MAT4") return 16;
    return 0;
}

bool GltfBuffers::buffer(size_t index, const std::vector<std::uint8_t>*& bytes,
                         std::string& error) {
    const nlohmann::json& buffers = m_doc.value("buffers", nlohmann::json::array());
    if (!buffers.is_array() || index >= buffers.size() || !buffers[index].is_object()) {
        error = "buffer " + std::to_string(index) + " does not exist";
        return false;
    }
    if (m_buffers.size() < buffers.size()) {
        m_buffers.resize(buffers.size());
        m_loaded.resize(buffers.size(), 0);
    }
    if (!m_loaded[index]) {
        const nlohmann::json& b = buffers[index];
        std::vector<std::uint8_t>& out = m_buffers[index];
        if (!b.contains("uri")) {
            if (!glbBinChunk(m_path, out)) {
                error = "buffer " + std::to_string(index) + " has no uri and the file no BIN chunk";
                return false;
            }
        } else if (!b["uri"].is_string()) {
            error = "buffer " + std::to_string(index) + ": its uri is not a string";
            return false;
        } else if (const std::string uri = b["uri"].get<std::string>();
                   uri.rfind("data:", 0) == 0) {
            const size_t comma = uri.find(";base64,");
            bool ok = comma != std::string::npos;
            if (ok) out = fromBase64(uri, comma + 8, ok);
            if (!ok) {
                error = "buffer " + std::to_string(index) + ": a data URI that is not base64";
                return false;
            }
        } else {
            const auto file = std::filesystem::path(m_path).parent_path() / percentDecoded(uri);
            std::ifstream in(file, std::ios::binary);
            if (!in) {
                error = "buffer " + std::to_string(index) + ": cannot read " + file.string();
                return false;
            }
            out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        }
        size_t length = 0;
        if (unsignedField(b, "byteLength", length) && out.size() < length) {
            error = "buffer " + std::to_string(index) + " holds " + std::to_string(out.size()) +
                    " bytes, fewer than its byteLength " + std::to_string(length);
            return false;
        }
        m_loaded[index] = 1;
    }
    bytes = &m_buffers[index];
    return true;
}

bool GltfBuffers::readImage(size_t index, std::vector<std::uint8_t>& out, std::string& error) {
    const nlohmann::json& images = m_doc.value("images", nlohmann::json::array());
    if (!images.is_array() || index >= images.size() || !images[index].is_object()) {
        error = "image " + std::to_string(index) + " does not exist";
        return false;
    }
    const nlohmann::json& image = images[index];
    const std::string name = "image " + std::to_string(index);
    if (image.contains("uri")) {
        const std::string uri = image["uri"].is_string() ? image["uri"].get<std::string>() : "";
        const size_t comma = uri.find(";base64,");
        bool ok = uri.rfind("data:", 0) == 0 && comma != std::string::npos;
        if (ok) out = fromBase64(uri, comma + 8, ok);
        if (!ok) error = name + ": its uri is no base64 data URI";
        return ok;
    }
    size_t viewIndex = 0, bufferIndex = 0, offset = 0, length = 0;
    const nlohmann::json& views = m_doc.value("bufferViews", nlohmann::json::array());
    if (!unsignedField(image, "bufferView", viewIndex) || !views.is_array() ||
        viewIndex >= views.size() || !views[viewIndex].is_object()) {
        error = name + " has neither a uri nor a bufferView that exists";
        return false;
    }
    const nlohmann::json& view = views[viewIndex];
    const std::string viewName = "bufferView " + std::to_string(viewIndex);
    if (!unsignedField(view, "buffer", bufferIndex) || !unsignedField(view, "byteLength", length) ||
        (view.contains("byteOffset") && !unsignedField(view, "byteOffset", offset))) {
        error = name + ": " + viewName + " has no buffer, byteLength or whole byteOffset";
        return false;
    }
    const std::vector<std::uint8_t>* bytes = nullptr;
    if (!buffer(bufferIndex, bytes, error)) {
        error = name + ": " + error;
        return false;
    }
    // Subtracting from the size known to be larger: no offset or length can wrap round.
    if (offset > bytes->size() || length > bytes->size() - offset) {
        error = name + ": " + viewName + " runs past buffer " + std::to_string(bufferIndex) +
                "'s " + std::to_string(bytes->size()) + " bytes";
        return false;
    }
    out.assign(bytes->begin() + long(offset), bytes->begin() + long(offset + length));
    return true;
}

bool GltfBuffers::locate(const nlohmann::json& a, size_t count, int components, Span& span,
                         std::string& error) {
    span = Span{};
    size_t viewIndex = 0;
    if (!a.contains("bufferView")) return true; // all zeros (§3.6.2.3)
    const nlohmann::json& views = m_doc.value("bufferViews", nlohmann::json::array());
    if (!unsignedField(a, "bufferView", viewIndex) || !views.is_array() ||
        viewIndex >= views.size() || !views[viewIndex].is_object()) {
        error = "its bufferView " + a["bufferView"].dump() + " does not exist";
        return false;
    }
    const nlohmann::json& view = views[viewIndex];
    const std::string viewName = "bufferView " + std::to_string(viewIndex);
    const std::string viewOwns = viewName + "'s";
    size_t bufferIndex = 0, viewOffset = 0, viewLength = 0, accessorOffset = 0, stride = 0;
    if (!unsignedField(view, "buffer", bufferIndex) ||
        !unsignedField(view, "byteLength", viewLength)) {
        error = viewName + " has no buffer or byteLength";
        return false;
    }
    // Absent is 0; present, each must be a whole number of bytes: a negative one would wrap
    // round to a pointer far outside the buffer.
    for (const auto& [object, key, out, owner] :
         {std::tuple{&view, "byteOffset", &viewOffset, viewOwns},
          std::tuple{&view, "byteStride", &stride, viewOwns},
          std::tuple{&a, "byteOffset", &accessorOffset, std::string("its")}})
        if (object->contains(key) && !unsignedField(*object, key, *out)) {
            error = owner + " " + key + " " + (*object)[key].dump() + " is not a whole number ≥ 0";
            return false;
        }
    span.type = a.value("componentType", 0);
    span.size = componentSize(span.type);
    if (span.size == 0) {
        error = "its componentType " + std::to_string(span.type) + " is not one glTF defines";
        return false;
    }
    const size_t element = span.size * size_t(components);
    if (stride == 0) stride = element;
    const std::vector<std::uint8_t>* bytes = nullptr;
    if (!buffer(bufferIndex, bytes, error)) return false;
    // Every comparison subtracts from a size already known to be larger, so that no offset,
    // stride or count can wrap round and pass.
    if (viewOffset > bytes->size() || viewLength > bytes->size() - viewOffset) {
        error = viewName + " (byteOffset " + std::to_string(viewOffset) + ", byteLength " +
                std::to_string(viewLength) + ") runs past buffer " + std::to_string(bufferIndex) +
                "'s " + std::to_string(bytes->size()) + " bytes";
        return false;
    }
    if (accessorOffset > viewLength) {
        error = "its byteOffset " + std::to_string(accessorOffset) + " is past the end of " +
                viewName + " (" + std::to_string(viewLength) + " bytes)";
        return false;
    }
    const size_t room = viewLength - accessorOffset;
    if (count > 0 && (element > room || (count - 1) > (room - element) / stride)) {
        error = "its " + std::to_string(count) + " elements run past " + viewName + " (" +
                std::to_string(element) + " bytes each, " + std::to_string(stride) +
                " apart, from byteOffset " + std::to_string(accessorOffset) + " of " +
                std::to_string(viewLength) + ")";
        return false;
    }
    span.base = bytes->data() + viewOffset + accessorOffset;
    span.stride = stride;
    return true;
}

bool GltfBuffers::readDense(const nlohmann::json& a, size_t count, int components,
                            std::vector<float>& out, std::string& error) {
    // Checked before anything is allocated: a count no buffer backs is refused, and an
    // accessor of zeros (no bufferView) may not ask for more than 2^28 values (1 GiB).
    Span span;
    if (!locate(a, count, components, span, error)) return false;
    if (!span.base && count * size_t(components) > (size_t(1) << 28)) {
        error = "an accessor without a bufferView of " + std::to_string(count) +
                " elements: more than dhdr reads";
        return false;
    }
    out.assign(count * size_t(components), 0.0f);
    if (!span.base) return true;
    const bool normalized = a.value("normalized", false);
    for (size_t i = 0; i < count; ++i)
        for (int c = 0; c < components; ++c)
            out[i * size_t(components) + size_t(c)] = component(
                span.base + i * span.stride + size_t(c) * span.size, span.type, normalized);
    return true;
}

bool GltfBuffers::readIndices(size_t index, std::vector<std::uint32_t>& out, std::string& error) {
    const nlohmann::json& accessors = m_doc.value("accessors", nlohmann::json::array());
    const std::string prefix = "accessor " + std::to_string(index) + ": ";
    size_t count = 0;
    if (!accessors.is_array() || index >= accessors.size() || !accessors[index].is_object() ||
        accessors[index].value("type", std::string()) != "SCALAR" ||
        !unsignedField(accessors[index], "count", count) || count > (size_t(1) << 32) ||
        accessors[index].contains("sparse")) {
        error = prefix + "not a dense SCALAR accessor of indices";
        return false;
    }
    const nlohmann::json& a = accessors[index];
    const int type = a.value("componentType", 0);
    if (type != 5121 && type != 5123 && type != 5125) {
        error = prefix + "indices must be unsigned bytes, shorts or ints";
        return false;
    }
    Span span;
    if (!locate(a, count, 1, span, error)) return error = prefix + error, false;
    if (!span.base && count > (size_t(1) << 28)) {
        error = prefix + "an index accessor without a bufferView: more indices than dhdr reads";
        return false;
    }
    out.assign(count, 0);
    if (!span.base) return true;
    for (size_t i = 0; i < count; ++i) {
        const std::uint8_t* p = span.base + i * span.stride;
        if (type == 5121)
            out[i] = *p;
        else if (type == 5123) {
            std::uint16_t v;
            std::memcpy(&v, p, 2);
            out[i] = v;
        } else
            std::memcpy(&out[i], p, 4);
    }
    return true;
}

bool GltfBuffers::readFloats(size_t index, std::vector<float>& out, int& components,
                             std::string& error) {
    const nlohmann::json& accessors = m_doc.value("accessors", nlohmann::json::array());
    if (!accessors.is_array() || index >= accessors.size() || !accessors[index].is_object()) {
        error = "accessor " + std::to_string(index) + " does not exist";
        return false;
    }
    const nlohmann::json& a = accessors[index];
    const std::string prefix = "accessor " + std::to_string(index) + ": ";
    size_t count = 0;
    components = a.contains("type") && a["type"].is_string()
                     ? gltfComponents(a["type"].get<std::string>())
                     : 0;
    if (components == 0 || !unsignedField(a, "count", count) || count > (size_t(1) << 32)) {
        error = prefix + "no valid type or count";
        return false;
    }
    if (!readDense(a, count, components, out, error)) {
        error = prefix + error;
        return false;
    }
    if (!a.contains("sparse")) return true;
    // Sparse: indices and values replace elements of the dense data.
    const nlohmann::json& s = a["sparse"];
    size_t n = 0;
    if (!s.is_object() || !unsignedField(s, "count", n) || !s.contains("indices") ||
        !s.contains("values") || n > count) {
        error = prefix + "a malformed sparse object";
        return false;
    }
    nlohmann::json indices = s["indices"], values = s["values"];
    indices["count"] = n;
    indices["type"] = "SCALAR";
    values["count"] = n;
    values["componentType"] = a.value("componentType", 0);
    values["normalized"] = a.value("normalized", false);
    std::vector<float> where, what;
    if (!readDense(indices, n, 1, where, error) || !readDense(values, n, components, what, error)) {
        error = prefix + "sparse: " + error;
        return false;
    }
    for (size_t k = 0; k < n; ++k) {
        const size_t i = size_t(where[k]);
        if (!(where[k] >= 0.0f) || i >= count) {
            error = prefix + "sparse index " + std::to_string(where[k]) + " is past its count";
            return false;
        }
        std::copy_n(&what[k * size_t(components)], components, &out[i * size_t(components)]);
    }
    return true;
}

} // namespace dhdr::detail
