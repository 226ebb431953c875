// Decoding base-colour textures through OpenImageIO.
#pragma once

#include <dhdr/deferred/scene.h>
#include <string>

namespace dhdr::detail {

// Reads an image file (or, with `size` > 0, encoded bytes in memory, e.g. a PNG inside a .glb)
// into linear RGBA: 8- and 16-bit images are taken as sRGB-encoded, as glTF specifies for
// base colour.
bool loadTexture(Texture& texture, const std::string& name, const void* data, size_t size,
                 std::string& error);

} // namespace dhdr::detail
