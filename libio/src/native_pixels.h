// Pixels in the types a file stores (ImageInput/ImageOutput native layout: each channel in
// its own type, one after the other) to float and back.
#pragma once

#include <OpenImageIO/imageio.h>
#include <cstddef>
#include <vector>

namespace dhdr {

// How ImageInput::read_native_scanlines packs a pixel of channels [chbegin, chend), and its
// conversion to float: OpenImageIO's, except that uint channels (object ids) keep their
// integer values instead of being scaled from [0, 2^32 − 1] to [0, 1].
struct NativeReader {
    std::vector<OIIO::TypeDesc> types;
    std::vector<size_t> offsets;
    size_t bytes = 0;
    bool uniform = true;

    NativeReader(const OIIO::ImageSpec& spec, int chbegin, int chend);
    // width × height pixels from `native` to float.
    bool toFloat(const std::byte* native, float* pixels, int width, int height) const;
};

// Float pixels as a file of `spec`'s channel types holds them, packed per pixel, each channel
// in its own type (ImageInput's native layout). Half is clamped to ±65504 and float to its
// largest finite value, NaN becomes 0, and uint channels take the rounded integer value,
// clamped to [0, 2^32 − 1]; `clamped` and `nonFinite` count what was changed. The channel
// named in `infinityAllowed` (a G-buffer's Z, +Inf on the background by contract) keeps +Inf.
struct NativeWriter {
    explicit NativeWriter(const OIIO::ImageSpec& spec, int infinityAllowed = -1);
    size_t pixelBytes() const { return m_bytes; }
    void convert(const float* pixels, size_t count, std::byte* native, long long& clamped,
                 long long& nonFinite) const;

private:
    std::vector<OIIO::TypeDesc> m_types;
    std::vector<size_t> m_offsets;
    size_t m_bytes = 0;
    int m_infinity = -1;
};

} // namespace dhdr
