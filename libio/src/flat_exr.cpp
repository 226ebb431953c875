#include "flat_exr.h"

#include "exr_spec_header.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfThreading.h>
#include <exception>
#include <string>
#include <vector>

namespace dhdr::detail {

namespace {

Imf::PixelType pixelType(OIIO::TypeDesc t) {
    if (t == OIIO::TypeDesc::HALF) return Imf::HALF;
    if (t == OIIO::TypeDesc::UINT) return Imf::UINT;
    return Imf::FLOAT;
}

} // namespace

struct FlatScanlineWriter::Impl {
    std::unique_ptr<Imf::OutputFile> file;
    OIIO::ImageSpec spec;
    std::vector<size_t> offsets; // each channel's bytes into a packed pixel
    size_t pixelBytes = 0;
};

FlatScanlineWriter::FlatScanlineWriter() = default;
FlatScanlineWriter::~FlatScanlineWriter() = default;

bool FlatScanlineWriter::open(const std::string& path, const OIIO::ImageSpec& spec,
                              const std::string& compression, std::string& error) {
    try {
        Imf::Header header = exrHeaderFromSpec(spec);
        int level = -1;
        if (!exrCompression(compression.empty() ? "zip" : compression, header.compression(),
                            level)) {
            error = "unknown EXR compression '" + compression + "'";
            return false;
        }
        if (level >= 0 && header.compression() <= Imf::ZIP_COMPRESSION)
            header.zipCompressionLevel() = level;
        else if (level >= 0)
            header.dwaCompressionLevel() = float(level);
        auto impl = std::make_unique<Impl>();
        impl->spec = spec;
        for (int c = 0; c < spec.nchannels; ++c) {
            header.channels().insert(spec.channelnames[size_t(c)],
                                     Imf::Channel(pixelType(spec.channelformat(c))));
            impl->offsets.push_back(impl->pixelBytes);
            impl->pixelBytes += spec.channelformat(c).size();
        }
        // OpenImageIO's EXR writer sizes OpenEXR's global pool the same way at each open.
        const int threads = exrThreads();
        if (Imf::globalThreadCount() != threads) Imf::setGlobalThreadCount(threads);
        impl->file = std::make_unique<Imf::OutputFile>(path.c_str(), header, threads);
        m_impl = std::move(impl);
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

bool FlatScanlineWriter::write(int ybegin, int yend, const std::byte* pixels, std::string& error) {
    if (!m_impl) {
        error = "not open";
        return false;
    }
    try {
        const OIIO::ImageSpec& spec = m_impl->spec;
        const size_t xStride = m_impl->pixelBytes, yStride = xStride * size_t(spec.width);
        // OpenEXR addresses a pixel by its (x, y) in the data window: the base is the address
        // pixel (0, 0) would have, in 64-bit arithmetic.
        const std::ptrdiff_t origin =
            std::ptrdiff_t(ybegin) * std::ptrdiff_t(yStride) + std::ptrdiff_t(spec.x) * xStride;
        char* base = const_cast<char*>(reinterpret_cast<const char*>(pixels)) - origin;
        Imf::FrameBuffer fb;
        for (int c = 0; c < spec.nchannels; ++c)
            fb.insert(spec.channelnames[size_t(c)],
                      Imf::Slice(pixelType(spec.channelformat(c)),
                                 base + m_impl->offsets[size_t(c)], xStride, yStride));
        m_impl->file->setFrameBuffer(fb);
        m_impl->file->writePixels(yend - ybegin);
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

bool FlatScanlineWriter::close(std::string& error) {
    try {
        // OpenEXR would close a file short of rows without a word, its offsets left 0.
        if (m_impl) {
            const int end = m_impl->spec.y + m_impl->spec.height;
            if (const int at = m_impl->file->currentScanLine(); at != end) {
                error = "rows " + std::to_string(at) + " to " + std::to_string(end - 1) +
                        " were never written";
                return false;
            }
        }
        m_impl.reset(); // the destructor writes the line offsets
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

} // namespace dhdr::detail
