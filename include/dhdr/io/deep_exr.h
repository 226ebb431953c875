// Deep scanline OpenEXR rows read and written through OpenEXR itself. OpenImageIO 2.4.7's
// deep scanline reads and writes compute each row's pointer offset in 32-bit ints and crash
// once y × width × channels reaches 2^31 (a 15360-wide deep G-buffer of 27 channels past row
// 5,177); OpenEXR's own DeepFrameBuffer takes 64-bit strides (docs/gbuffer.md).
#pragma once

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imageio.h>
#include <memory>
#include <string>

namespace dhdr {

class DeepScanlineReader {
public:
    DeepScanlineReader();
    ~DeepScanlineReader();
    // Part `part` of `path`, a deep scanline EXR; `spec` is OpenImageIO's spec of that part
    // (channels in its order).
    bool open(const std::string& path, int part, const OIIO::ImageSpec& spec, std::string& error);
    // Rows [ybegin, yend) into `out`, every channel in its file type, as
    // ImageInput::read_native_deep_scanlines gives them.
    bool read(int ybegin, int yend, OIIO::DeepData& out, std::string& error);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

class DeepScanlineWriter {
public:
    DeepScanlineWriter();
    ~DeepScanlineWriter();
    // A deep scanline EXR with `spec`'s windows, channels (channelformats, or format) and
    // attributes (strings, string lists, ints, floats, 2- and 3-vectors, 4×4 matrices),
    // ZIPS-compressed (OpenEXR 3.1 takes only NONE, RLE and ZIPS for deep parts), at the zip
    // level of the spec's "compression" when it names one ("zips:1"), its line blocks
    // compressed on OpenEXR's pool (OpenImageIO's "exr_threads").
    bool open(const std::string& path, const OIIO::ImageSpec& spec, std::string& error);
    // Rows [ybegin, yend), in order; `samples` holds their pixels with the spec's channel types.
    bool write(int ybegin, int yend, const OIIO::DeepData& samples, std::string& error);
    bool close(std::string& error);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace dhdr
