#include "png_header.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/strutil.h>
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <limits>
#include <memory>
#include <vector>
#include <zlib.h>

namespace dhdr::detail {

namespace {

constexpr size_t kSignature = 8;

uint32_t bigEndian32(const unsigned char* p) {
    return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

void putBigEndian32(unsigned char* p, uint32_t v) {
    p[0] = static_cast<unsigned char>(v >> 24);
    p[1] = static_cast<unsigned char>(v >> 16);
    p[2] = static_cast<unsigned char>(v >> 8);
    p[3] = static_cast<unsigned char>(v);
}

template <class T>
void deassociate(T* data, size_t pixels, int channels, int alpha) {
    // OpenImageIO 2.4 pngoutput.cpp, deassociateAlpha with gamma 1.
    const unsigned int max = std::numeric_limits<T>::max();
    for (size_t x = 0; x < pixels; ++x, data += channels) {
        // Opaque pixels divide to themselves: skipped, as most are.
        if (!data[alpha] || data[alpha] == max) continue;
        for (int c = 0; c < channels; ++c)
            if (c != alpha) data[c] = T(std::min(max, unsigned(data[c]) * max / data[alpha]));
    }
}

} // namespace

void appendPngChunk(std::string& out, const char type[4], const void* data, size_t size) {
    unsigned char length[4];
    putBigEndian32(length, uint32_t(size));
    out.append(reinterpret_cast<const char*>(length), 4);
    const size_t typeAt = out.size();
    out.append(type, 4);
    out.append(static_cast<const char*>(data), size);
    uLong crc = crc32(0L, Z_NULL, 0);
    crc = crc32_z(crc, reinterpret_cast<const Bytef*>(out.data() + typeAt), size + 4);
    unsigned char tail[4];
    putBigEndian32(tail, uint32_t(crc));
    out.append(reinterpret_cast<const char*>(tail), 4);
}

bool pngHeader(const OIIO::ImageSpec& spec, std::string& bytes, std::string& error) {
    OIIO::ImageSpec one = spec;
    one.width = one.height = 1;
    one.tile_width = one.tile_height = one.tile_depth = 0;
    OIIO::Filesystem::IOVecOutput memory;
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("header.png");
    const std::vector<unsigned char> pixel(one.pixel_bytes(), 0);
    if (!out || !out->set_ioproxy(&memory) || !out->open("header.png", one) ||
        !out->write_image(one.format, pixel.data()) || !out->close()) {
        error = out ? out->geterror() : OIIO::geterror();
        return false;
    }
    const std::vector<unsigned char>& file = memory.buffer();
    // Chunks up to the first IDAT; the writer's IHDR comes first (PNG requires it).
    size_t at = kSignature;
    while (at + 12 <= file.size() &&
           std::string(reinterpret_cast<const char*>(&file[at + 4]), 4) != "IDAT")
        at += 12 + bigEndian32(&file[at]);
    if (at + 12 > file.size() || file.size() < kSignature + 33 ||
        std::string(reinterpret_cast<const char*>(&file[kSignature + 4]), 4) != "IHDR") {
        error = "OpenImageIO's PNG header has no IHDR or IDAT";
        return false;
    }
    bytes.assign(file.begin(), file.begin() + kSignature);
    unsigned char ihdr[13];
    std::copy(&file[kSignature + 8], &file[kSignature + 8 + 13], ihdr);
    putBigEndian32(ihdr, uint32_t(spec.width));
    putBigEndian32(ihdr + 4, uint32_t(spec.height));
    appendPngChunk(bytes, "IHDR", ihdr, sizeof ihdr);
    bytes.append(reinterpret_cast<const char*>(&file[kSignature + 25]),
                 reinterpret_cast<const char*>(&file[at]));
    return true;
}

int pngAlphaChannel(const OIIO::ImageSpec& spec) {
    // OpenImageIO 2.4 png_pvt.h, create_write_struct: PNG's colour types decide alpha, not
    // the spec; and it is divided out unless the spec says it is unassociated.
    const int alpha = spec.nchannels == 2 ? 1 : spec.nchannels == 4 ? 3 : -1;
    return spec.get_int_attribute("oiio:UnassociatedAlpha", 0) ? -1 : alpha;
}

float pngAlphaGamma(const OIIO::ImageSpec& spec) {
    // OpenImageIO 2.4 png_pvt.h, write_info: "oiio:Gamma", or the number of a "GammaX"
    // colour space when it is sane.
    float gamma = spec.get_float_attribute("oiio:Gamma", 1.0f);
    const std::string colorspace = spec.get_string_attribute("oiio:ColorSpace");
    if (OIIO::Strutil::istarts_with(colorspace, "Gamma")) {
        OIIO::string_view rest = colorspace;
        OIIO::Strutil::parse_word(rest);
        const float g = OIIO::Strutil::from_string<float>(rest);
        if (g >= 0.01f && g <= 10.0f) gamma = g;
    }
    return gamma;
}

void pngDeassociate(uint8_t* data, size_t pixels, int channels, int alpha) {
    deassociate(data, pixels, channels, alpha);
}

void pngDeassociate(uint16_t* data, size_t pixels, int channels, int alpha) {
    deassociate(data, pixels, channels, alpha);
}

} // namespace dhdr::detail
