// Flat scanline OpenEXR rows written through OpenEXR itself, straight from the packed
// per-pixel buffer NativeWriter fills: OpenImageIO 2.4's write_scanlines copies each strip
// into a buffer of its own (allocated and page-faulted a strip at a time) before OpenEXR
// copies it again, which cost a G-buffer write as much as a third of its compression.
#pragma once

#include <OpenImageIO/imageio.h>
#include <cstddef>
#include <memory>
#include <string>

namespace dhdr::detail {

class FlatScanlineWriter {
public:
    FlatScanlineWriter();
    ~FlatScanlineWriter();
    // A single-part scanline EXR of `spec`'s windows, channels (each in spec.channelformat,
    // half, float or uint) and attributes (exrHeaderFromSpec), compressed as `compression`
    // names it (exrCompression), lines in increasing y; OpenEXR's pool compresses line blocks
    // in parallel (exrThreads), and the file's bytes do not depend on how many threads it has.
    bool open(const std::string& path, const OIIO::ImageSpec& spec, const std::string& compression,
              std::string& error);
    // Rows [ybegin, yend), in order, packed as NativeWriter packs them.
    bool write(int ybegin, int yend, const std::byte* pixels, std::string& error);
    bool close(std::string& error);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace dhdr::detail
