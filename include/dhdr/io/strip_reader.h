// Reading an image a strip of rows at a time, so that a stage's memory does not grow with
// the frame (dhdr-light, dhdr-aa and dhdr-bloom stream their frames this way).
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <dhdr/io/deep_exr.h>
#include <memory>
#include <string>
#include <vector>

namespace dhdr {

class StripReader {
public:
    // Opens channels [chbegin, chend) of part `subimage` of `path`. False with `error` when
    // the file cannot be read, is deep, or is larger than this machine's memory could hold
    // (for files read whole, below). With `frontSamples`, a deep part is read too, each pixel
    // its front sample: a deep G-buffer's nearest surfaces (never a deep picture, which must
    // be composited); deep scanlines strip by strip, deep tiles whole.
    bool open(const std::string& path, int subimage, int chbegin, int chend, int nthreads,
              std::string& error, bool frontSamples = false);
    // The file's spec for the channels read, as float pixels (metadata kept).
    const OIIO::ImageSpec& spec() const { return m_spec; }
    // Rows [ybegin, yend) (clamped to the image) as float pixels into `strip`, whose origin
    // is then (spec().x, ybegin). Uint channels hold their integer values. `strip`'s memory
    // is reused when its size allows.
    // With `reuse` (float rows of this image, as read() gave them, not `strip`): the rows it
    // holds from ybegin on are copied from it rather than decoded again (the halo that two
    // strips share); `copiedEnd` (optional) is then the end of those rows (ybegin: none).
    bool read(int ybegin, int yend, OIIO::ImageBuf& strip, std::string& error,
              const OIIO::ImageBuf* reuse = nullptr, int* copiedEnd = nullptr);
    // Scanline OpenEXR is read strip by strip; other files (tiled EXR, other formats) are
    // read whole once and served from memory.
    bool streamed() const { return !m_whole.initialized(); }

private:
    // Rows [ybegin, yend) of the image, decoded into `out` (rows of spec()'s width and channels).
    bool decode(int ybegin, int yend, float* out, std::string& error);

    std::string m_path;
    int m_workers = 1;
    // One reader per worker: a strip's bands of rows are decoded on every core at once
    // (OpenEXR decodes the chunks of one read call on one thread here).
    std::vector<std::unique_ptr<OIIO::ImageInput>> m_inputs;
    std::unique_ptr<OIIO::ImageInput> m_in;     // until the first read
    std::unique_ptr<DeepScanlineReader> m_deep; // a deep scanline part, front samples
    OIIO::ImageSpec m_deepSpec;
    std::unique_ptr<OIIO::ImageSpec> m_native_spec; // the part's spec as in the file
    OIIO::ImageSpec m_spec;
    OIIO::ImageBuf m_whole;
    std::vector<std::byte> m_native;
    int m_subimage = 0, m_chbegin = 0, m_chend = 0;
};

} // namespace dhdr
