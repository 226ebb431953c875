// A deep G-buffer (docs/gbuffer.md, "Deep G-buffers"): per pixel, every surface along the
// primary ray up to the first opaque one, front to back, each sample with the contract's
// channels. In files it is a deep scanline OpenEXR; in memory, samples packed pixel after
// pixel as float.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <cstdint>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <memory>
#include <string>
#include <vector>

namespace dhdr {

struct DeepGBuffer {
    // Size, data window and header attributes (camera, name tables) of the frame, with
    // deepChannelNames() as its channels, with the WhenUsed ones of the file it was read from;
    // not itself deep.
    OIIO::ImageSpec spec;
    // Index of each pixel's first sample, pixel by pixel in scanline order, and one past
    // the last at the end: width × height + 1 entries.
    std::vector<std::uint32_t> first;
    // spec.nchannels floats per sample.
    std::vector<float> values;

    int samples(int x, int y) const {
        const size_t p = pixel(x, y);
        return int(first[p + 1] - first[p]);
    }
    const float* sample(int x, int y, int k) const {
        return &values[(size_t(first[pixel(x, y)]) + size_t(k)) * size_t(spec.nchannels)];
    }
    size_t totalSamples() const { return first.empty() ? 0 : size_t(first.back()); }
    size_t pixel(int x, int y) const {
        return size_t(y - spec.y) * size_t(spec.width) + size_t(x - spec.x);
    }
};

// A deep G-buffer read a band of rows at a time, so that memory follows the band's samples,
// not the frame's. Samples are sorted front to back by Z (stably: equal depths keep the
// file's order); a sample with ZBack > Z is a volume, not a surface, and is an error, as is a
// missing contract channel (emission and ids are optional: zero). Non-finite values other
// than Z are replaced by 0 and counted. Errors say why, without the path.
class DeepGBufferReader {
public:
    DeepGBufferReader();
    ~DeepGBufferReader();
    // Part `subimage` of a deep scanline or tiled EXR (a tiled one is read whole on the first
    // read and served from memory).
    bool open(const std::string& path, int subimage, std::string& error);
    // The frame as a DeepGBuffer's spec: the whole data window, deepChannelNames(), float.
    const OIIO::ImageSpec& spec() const { return m_spec; }
    // Rows [ybegin, yend) (within the frame) into `out`, whose spec is then spec() cut to them.
    bool read(int ybegin, int yend, DeepGBuffer& out, std::string& error,
              long long* replaced = nullptr);

private:
    struct File;
    std::unique_ptr<File> m_file;
    OIIO::ImageSpec m_spec;
};

// The whole of part `subimage` (DeepGBufferReader's rules).
bool readDeepGBuffer(const std::string& path, int subimage, DeepGBuffer& out, std::string& error,
                     long long* replaced = nullptr);

// The samples of rows [ybegin, yend) of `g` as OIIO DeepData, ready for
// ImageOutput::write_deep_scanlines: in `formats` (one type a channel; empty: the deep
// G-buffer contract's, gbuffer::channelFormats of its channels).
void toDeepData(const DeepGBuffer& g, int ybegin, int yend, OIIO::DeepData& out,
                std::vector<OIIO::TypeDesc> formats = {});

} // namespace dhdr
