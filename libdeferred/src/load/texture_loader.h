// Decoding textures through OpenImageIO.
#pragma once

#include <dhdr/deferred/scene/scene.h>
#include <string>

namespace dhdr::detail {

// Reads an image file (or, with `size` > 0, encoded bytes in memory, e.g. a PNG inside a .glb)
// into RGBA floats. With `srgb` (glTF's base colour and emissive textures), 8- and 16-bit
// images are taken as sRGB-encoded and decoded to linear; without (normal and
// metallic-roughness maps), their values are kept as they are.
bool loadTexture(Texture& texture, const std::string& name, const void* data, size_t size,
                 bool srgb, std::string& error);

} // namespace dhdr::detail
