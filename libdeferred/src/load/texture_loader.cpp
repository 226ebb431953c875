#include "load/texture_loader.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <cmath>
#include <dhdr/io/exr_header.h>
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
    OIIO::ImageBuf image(name, 0, 0, nullptr, size > 0 ? &config : nullptr);
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
    for (size_t i = 0; i < size_t(spec.width) * size_t(spec.height); ++i) {
        const float* p = &pixels[i * size_t(spec.nchannels)];
        float* q = &texture.rgba[i * 4];
        for (int c = 0; c < 3; ++c) {
            const float v = p[std::min(c, spec.nchannels - 1)];
            q[c] = encoded ? srgbDecode(v) : v;
        }
        if (spec.nchannels == 4 || spec.nchannels == 2) q[3] = p[spec.nchannels - 1];
    }
    return true;
}

} // namespace dhdr::detail
