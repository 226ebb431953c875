// Reading a scanline EXR on several threads at once, each decoding its own bands of rows.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace dhdr {

// Reads channels [chbegin, chend) of subimage (EXR part) `subimage` of `path` into `image` as
// float pixels, keeping the file's metadata. The EXR's uint channels (object ids) are read as
// their integer values, not scaled to [0, 1] as OpenImageIO's conversion does. Deep files and
// images larger than this machine's memory are refused before anything is allocated. A
// scanline OpenEXR file is decoded in bands of rows by
// `nthreads` threads (0: all cores), each with its own reader: OpenEXR's own thread pool
// parallelizes within a read call only, and OpenImageIO's conversion to float after it is
// serial. When `image` already holds float pixels of the same size (the previous frame of a
// sequence), they are overwritten rather than allocated again: a fresh 1080p frame costs
// ~8,000 page faults. Other files are read by ImageBuf::read. On failure `error` says what
// went wrong.
bool readBanded(const std::string& path, OIIO::ImageBuf& image, int chbegin, int chend,
                int nthreads, std::string& error, int subimage = 0);

// Part `subimage` of `path`, opened; null with `error` when it cannot be read or is deep (a
// list of samples per pixel, which no tool but the lighting of deep G-buffers takes).
std::unique_ptr<OIIO::ImageInput> openFlatPart(const std::string& path, int subimage,
                                               std::string& error);

// The spec of channels [chbegin, chend) of a file of spec `file`, read as float pixels:
// scanline, its metadata, alpha and depth channels renumbered (−1 when outside the run).
OIIO::ImageSpec floatChannelSpec(const OIIO::ImageSpec& file, int chbegin, int chend);

// Whether float pixels of `spec`'s size and `channels` fit this machine's memory; otherwise
// false with a message that names the size.
bool fitsInMemory(const OIIO::ImageSpec& spec, int channels, std::string& error);

} // namespace dhdr
