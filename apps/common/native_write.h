// Float pixels in the types a file stores, for writing: the other half of banded_read.
#pragma once

#include <OpenImageIO/imageio.h>
#include <cstddef>
#include <vector>

namespace dhdr::app {

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

} // namespace dhdr::app
