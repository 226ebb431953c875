// An 8- or 16-bit PNG written strip by strip, its deflate work spread over threads: each
// group of rows is deflated on its own (pigz's way: a raw stream ended by a sync flush,
// primed with the previous group's last 32 KiB) and the pieces are joined into the one zlib
// stream PNG requires; or the whole image deflated at once by libdeflate (whole). The chunks before
// the pixels are the ones OpenImageIO's PNG writer gives the same spec, and so are the decoded
// pixels; the file's bytes do not depend on the number of threads. Written under a temporary name
// and renamed into place by commit().
#pragma once

#include <OpenImageIO/oiioversion.h>
#include <memory>
#include <string>

OIIO_NAMESPACE_BEGIN
class ImageSpec;
OIIO_NAMESPACE_END

namespace dhdr {

struct PngWriteOptions {
    // Threads deflating groups of rows at once, [1, ∞); the bytes are the same for any.
    int nthreads = 1;
    // The whole image deflated in one call at the end (libdeflate, one thread), its rows
    // held until then: faster than groups for a frame held whole anyway, and the way for
    // frames that each have one thread (a sequence). The bytes differ from groups'.
    bool whole = false;
};

class PngFileWriter {
public:
    explicit PngFileWriter(std::string path);
    ~PngFileWriter(); // removes the temporary of an uncommitted file
    PngFileWriter(const PngFileWriter&) = delete;
    PngFileWriter& operator=(const PngFileWriter&) = delete;

    // Whether this writer gives for `spec` the pixels OpenImageIO's would: UINT8 or UINT16,
    // 1-4 channels, rows asked unfiltered ("png:filter" 8, libpng's PNG_FILTER_NONE: what
    // dhdr-tonemap asks for dithered 8-bit output), one subimage.
    static bool handles(const OIIO::ImageSpec& spec);
    // Opens the temporary for an image of `spec` (as handles() accepts).
    bool open(const OIIO::ImageSpec& spec, const PngWriteOptions& options);
    // Rows [ybegin, yend), the next ones in order: contiguous pixels of the spec's type and
    // channels, alpha associated as OpenImageIO takes it (it is divided out here as there).
    bool writeRows(int ybegin, int yend, const void* pixels);
    // Writes what is left, closes the file and renames it into place.
    bool commit();
    const std::string& path() const { return m_path; }
    // "PATH: what went wrong".
    const std::string& geterror() const { return m_error; }

private:
    struct Impl;
    std::string m_path, m_error;
    std::unique_ptr<Impl> m_impl;
};

} // namespace dhdr
