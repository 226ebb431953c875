#include <algorithm>
#include <cstdint>
#include <cstring>
#include <dhdr/io/exr_header.h>
#include <fstream>
#include <vector>

namespace dhdr::detail {

namespace {

// Headers are small: the first 64 MiB of a file are looked at; headers that go on past them
// (with every claim so far within the file) are left to OpenEXR.
constexpr std::uint64_t kMaxHeaderBytes = 64ull << 20;

struct Cursor {
    const std::vector<char>& bytes;
    size_t at = 0;

    bool cString(std::string& out, size_t maxLength) {
        out.clear();
        while (at < bytes.size() && bytes[at] != '\0') {
            if (out.size() >= maxLength) return false;
            out.push_back(bytes[at++]);
        }
        if (at >= bytes.size()) return false;
        ++at; // the terminating 0
        return true;
    }
    bool int32(std::int32_t& v) {
        if (bytes.size() - at < 4) return false;
        const auto* b = reinterpret_cast<const unsigned char*>(&bytes[at]);
        v = std::int32_t(std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 |
                         std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24);
        at += 4;
        return true;
    }
};

// OpenEXR 3.1 does not skip an attribute by the size it states: it reads the value as its type
// says (16 bytes of a box2i, a channel list up to its closing 0) and goes on from there. An
// attribute whose size disagrees with its value would be read from elsewhere than it is
// looked at here, so it is refused. The bytes each fixed-size type reads:
int fixedSize(const std::string& type) {
    static const struct {
        const char* type;
        int bytes;
    } kTypes[] = {{"box2i", 16},
                  {"box2f", 16},
                  {"chromaticities", 32},
                  {"compression", 1},
                  {"deepImageState", 1},
                  {"double", 8},
                  {"envmap", 1},
                  {"float", 4},
                  {"int", 4},
                  {"keycode", 28},
                  {"lineOrder", 1},
                  {"m33f", 36},
                  {"m33d", 72},
                  {"m44f", 64},
                  {"m44d", 128},
                  {"rational", 8},
                  {"tiledesc", 9},
                  {"timecode", 8},
                  {"v2i", 8},
                  {"v2f", 8},
                  {"v2d", 16},
                  {"v3i", 12},
                  {"v3f", 12},
                  {"v3d", 24}};
    for (const auto& t : kTypes)
        if (type == t.type) return t.bytes;
    return -1;
}

// The value of an attribute of `size` bytes read as OpenEXR 3.1 reads it: exactly those bytes,
// nothing it allocates by before reading past them, and a channel list whose pixel types
// OpenImageIO 2.4 knows.
bool valueFits(const std::string& type, const char* value, std::int32_t size) {
    auto u32 = [&](size_t offset) {
        const auto* b = reinterpret_cast<const unsigned char*>(value + offset);
        return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 |
               std::uint32_t(b[3]) << 24;
    };
    if (const int bytes = fixedSize(type); bytes >= 0) return size == bytes;
    if (type == "preview") {
        // width, height, then 4 bytes a texel.
        if (size < 8) return false;
        return 8 + 4 * std::uint64_t(u32(0)) * std::uint64_t(u32(4)) == std::uint64_t(size);
    }
    if (type == "chlist") {
        // Per channel: its name, pixel type, pLinear and 3 reserved bytes, x and y sampling;
        // a 0 where a name would start ends the list, as the attribute's last byte.
        // OpenImageIO 2.4 aborts (an assertion, Unknown Imf::PixelType) on a type other than
        // UINT 0, HALF 1 or FLOAT 2, which OpenEXR 3.1 reads without a word.
        std::int32_t at = 0;
        while (at < size && value[at] != '\0') {
            while (at < size && value[at] != '\0')
                ++at;
            if (size - at < 1 + 16) return false;
            ++at;
            const std::uint32_t pixelType = u32(size_t(at));
            if (pixelType > 2) return false;
            at += 16;
        }
        return at == size - 1;
    }
    if (type == "stringvector") {
        // Each string: its length, then its bytes, to the attribute's end.
        std::uint64_t at = 0;
        while (at < std::uint64_t(size)) {
            if (std::uint64_t(size) - at < 4) return false;
            const std::int32_t n = std::int32_t(u32(size_t(at)));
            at += 4;
            if (n < 0 || std::uint64_t(n) > std::uint64_t(size) - at) return false;
            at += std::uint64_t(n);
        }
        return true;
    }
    if (type == "floatvector") return size % 4 == 0;
    // string, and types OpenEXR does not know (read as opaque bytes): the size is what is read.
    return true;
}

} // namespace

bool exrHeadersFit(const std::string& path, std::string& error) {
    std::ifstream file(path, std::ios::binary | std::ios::ate);
    if (!file) return true; // the reader says why it cannot open it
    const std::uint64_t fileSize = std::uint64_t(file.tellg());
    file.seekg(0);
    std::vector<char> bytes(size_t(std::min(fileSize, kMaxHeaderBytes)));
    if (!file.read(bytes.data(), std::streamsize(bytes.size()))) return true;
    static const unsigned char kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
    if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 4) != 0) return true;
    const auto* v = reinterpret_cast<const unsigned char*>(bytes.data() + 4);
    const std::uint32_t flags = std::uint32_t(v[1]) << 8 | std::uint32_t(v[2]) << 16;
    const bool longNames = flags & 0x400, multipart = flags & 0x1000;
    const size_t maxName = longNames ? 255 : 31;
    Cursor in{bytes, 8};
    // Past the bytes read of a larger file nothing more can be said.
    const bool partial = bytes.size() < fileSize;
    for (int part = 0;; ++part) {
        std::string name, type;
        int attributes = 0;
        for (;; ++attributes) {
            if (!in.cString(name, maxName)) {
                if (partial && in.at >= bytes.size()) return true;
                error = "an OpenEXR header cut short or with a name longer than " +
                        std::to_string(maxName) + " bytes";
                return false;
            }
            if (name.empty()) break; // the end of this header
            std::int32_t size = 0;
            if (!in.cString(type, maxName) || !in.int32(size)) {
                if (partial && bytes.size() - in.at < 4) return true;
                error = "an OpenEXR header cut short in attribute '" + name + "'";
                return false;
            }
            if (partial && std::uint64_t(size) > bytes.size() - in.at &&
                std::uint64_t(size) <= fileSize - in.at)
                return true;
            if (size < 0 || std::uint64_t(size) > bytes.size() - in.at ||
                !valueFits(type, &bytes[in.at], size)) {
                const bool inFile = size >= 0 && std::uint64_t(size) <= bytes.size() - in.at;
                error = !inFile ? "OpenEXR attribute '" + name + "' (" + type + ") claims " +
                                      std::to_string(size) + " bytes, past the end of the " +
                                      std::to_string(fileSize) + "-byte file"
                        : type == "chlist"
                            ? "OpenEXR attribute '" + name +
                                  "' (chlist) is not a channel list of its size, or holds a "
                                  "channel of a pixel type OpenEXR does not define (not uint, "
                                  "half or float)"
                            : "OpenEXR attribute '" + name + "' (" + type +
                                  ") does not hold a value of its type in its " +
                                  std::to_string(size) + " bytes";
                return false;
            }
            in.at += size_t(size);
        }
        // A single-part file has one header; a multi-part file's list of headers ends with an
        // empty one (a lone 0 where the next header's first name would be).
        if (!multipart) return true;
        if (attributes == 0) return true;
        if (part > 100000) {
            error = "an OpenEXR file with more than 100000 parts";
            return false;
        }
    }
}

} // namespace dhdr::detail
