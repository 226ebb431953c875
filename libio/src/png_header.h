// The bytes of a PNG around its pixels, as OpenImageIO 2.4's PNG writer makes them: the
// chunks before the first IDAT, chunk framing, and its division of associated alpha.
#pragma once

#include <OpenImageIO/imageio.h>
#include <cstddef>
#include <cstdint>
#include <string>

namespace dhdr::detail {

// The signature and every chunk before the first IDAT that OpenImageIO writes for `spec`
// (IHDR, gAMA/sRGB/cHRM, oFFs, pHYs, tIME, tEXt…): taken from a 1×1 image it writes to
// memory, IHDR then given the spec's size. False with `error`.
bool pngHeader(const OIIO::ImageSpec& spec, std::string& bytes, std::string& error);

// Appends a chunk: length, type, data, CRC.
void appendPngChunk(std::string& out, const char type[4], const void* data, size_t size);

// How OpenImageIO's PNG writer turns associated alpha into PNG's unassociated alpha:
// the channel it divides by for `spec` (-1: none), and the gamma it does it with.
int pngAlphaChannel(const OIIO::ImageSpec& spec);
float pngAlphaGamma(const OIIO::ImageSpec& spec);

// Its division for gamma 1 (in integers, as there), `pixels` pixels of `channels` values.
void pngDeassociate(uint8_t* data, size_t pixels, int channels, int alpha);
void pngDeassociate(uint16_t* data, size_t pixels, int channels, int alpha);

} // namespace dhdr::detail
