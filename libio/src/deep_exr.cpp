#include "exr_spec_header.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDeepFrameBuffer.h>
#include <OpenEXR/ImfDeepScanLineInputPart.h>
#include <OpenEXR/ImfDeepScanLineOutputFile.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfThreading.h>
#include <cstdint>
#include <dhdr/io/deep_exr.h>
#include <dhdr/io/exr_header.h>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace dhdr {

namespace {

Imf::PixelType pixelType(OIIO::TypeDesc t) {
    if (t == OIIO::TypeDesc::HALF) return Imf::HALF;
    if (t == OIIO::TypeDesc::UINT) return Imf::UINT;
    return Imf::FLOAT;
}

// The frame buffer of rows [ybegin, yend) of `data`, whose pixels are those rows': OpenEXR
// addresses pixels by their (x, y) in the data window, so the bases are offset back to (0, 0)
// in 64-bit arithmetic (where OpenImageIO 2.4.7 overflows).
// `counts` holds the rows' sample counts, `pointers` each pixel's pointer to each channel of
// its first sample (DeepData::get_pointers), `sampleBytes` the distance between samples.
Imf::DeepFrameBuffer frameBuffer(const OIIO::ImageSpec& spec, int ybegin, unsigned* counts,
                                 const std::vector<OIIO::TypeDesc>& types,
                                 std::vector<void*>& pointers, size_t sampleBytes) {
    const std::ptrdiff_t width = spec.width, nch = spec.nchannels;
    const std::ptrdiff_t first = std::ptrdiff_t(ybegin) * width + spec.x;
    Imf::DeepFrameBuffer fb;
    fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, reinterpret_cast<char*>(counts - first),
                                         sizeof(unsigned), sizeof(unsigned) * size_t(width)));
    for (std::ptrdiff_t c = 0; c < nch; ++c)
        fb.insert(spec.channelnames[size_t(c)],
                  Imf::DeepSlice(pixelType(types[size_t(c)]),
                                 reinterpret_cast<char*>(pointers.data() + c - first * nch),
                                 sizeof(void*) * size_t(nch),
                                 sizeof(void*) * size_t(nch) * size_t(width), sampleBytes));
    return fb;
}

} // namespace

struct DeepScanlineReader::Impl {
    std::unique_ptr<Imf::MultiPartInputFile> file;
    std::unique_ptr<Imf::DeepScanLineInputPart> part;
    std::uintmax_t fileBytes = 0;
    OIIO::ImageSpec spec;
};

DeepScanlineReader::DeepScanlineReader() = default;
DeepScanlineReader::~DeepScanlineReader() = default;

bool DeepScanlineReader::open(const std::string& path, int part, const OIIO::ImageSpec& spec,
                              std::string& error) {
    if (!detail::exrHeadersFit(path, error)) return false;
    try {
        m_impl = std::make_unique<Impl>();
        // Line blocks decompressed in parallel, as the writer compresses them.
        const int threads = detail::exrThreads();
        if (Imf::globalThreadCount() != threads) Imf::setGlobalThreadCount(threads);
        m_impl->file = std::make_unique<Imf::MultiPartInputFile>(path.c_str(), threads);
        m_impl->part = std::make_unique<Imf::DeepScanLineInputPart>(*m_impl->file, part);
        m_impl->spec = spec;
        std::error_code ec;
        m_impl->fileBytes = std::filesystem::file_size(path, ec);
        if (ec) m_impl->fileBytes = 0;
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        m_impl.reset();
        return false;
    }
}

bool DeepScanlineReader::read(int ybegin, int yend, OIIO::DeepData& out, std::string& error) {
    if (!m_impl) {
        error = "not open";
        return false;
    }
    const OIIO::ImageSpec& spec = m_impl->spec;
    try {
        const size_t npix = size_t(spec.width) * size_t(yend - ybegin);
        std::vector<OIIO::TypeDesc> types;
        for (int c = 0; c < spec.nchannels; ++c)
            types.push_back(spec.channelformat(c));
        out.init(int64_t(npix), spec.nchannels, types, spec.channelnames);
        // The counts first, then room for the samples, then the samples. OpenEXR forgets the
        // counts when given a new frame buffer, so the slices are set once and their pointer
        // table (the same size before and after) is filled in place. The DeepData is not
        // touched before set_all_samples: once allocated, OpenImageIO 2.4 grows it pixel by
        // pixel, in time quadratic in the pixels.
        std::vector<unsigned> counts(npix, 0);
        std::vector<void*> pointers(npix * size_t(spec.nchannels), nullptr);
        m_impl->part->setFrameBuffer(
            frameBuffer(spec, ybegin, counts.data(), types, pointers, out.samplesize()));
        m_impl->part->readPixelSampleCounts(ybegin, yend - 1);
        // Counts a corrupt or hostile file claims are checked before anything is allocated for
        // them: deep parts are stored raw, RLE (at most 64:1) or deflate (at most 1032:1), so
        // samples that would unpack to more than 1032 bytes for each byte of the file cannot
        // be in it.
        std::uint64_t total = 0;
        for (const unsigned n : counts)
            total += n;
        const double bytes = double(total) * double(out.samplesize());
        if (m_impl->fileBytes > 0 && bytes > 1032.0 * double(m_impl->fileBytes) + 65536.0)
            throw std::runtime_error(
                "rows " + std::to_string(ybegin) + "-" + std::to_string(yend - 1) + " claim " +
                std::to_string(total) + " deep samples (" +
                std::to_string(std::uint64_t(bytes / 1048576.0)) + " MiB), more than the file's " +
                std::to_string(m_impl->fileBytes) + " bytes can hold");
        out.set_all_samples(counts);
        const void* const table = pointers.data();
        out.get_pointers(pointers);
        if (pointers.data() != table || pointers.size() != npix * size_t(spec.nchannels))
            throw std::runtime_error("deep pointer table moved");
        m_impl->part->readPixels(ybegin, yend - 1);
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

struct DeepScanlineWriter::Impl {
    std::unique_ptr<Imf::DeepScanLineOutputFile> file;
    OIIO::ImageSpec spec;
    std::vector<void*> pointers;
};

DeepScanlineWriter::DeepScanlineWriter() = default;
DeepScanlineWriter::~DeepScanlineWriter() = default;

bool DeepScanlineWriter::open(const std::string& path, const OIIO::ImageSpec& spec,
                              std::string& error) {
    try {
        Imf::Header header = detail::exrHeaderFromSpec(spec);
        header.setType(Imf::DEEPSCANLINE);
        header.compression() = Imf::ZIPS_COMPRESSION;
        // The spec's zip level ("zips:1"); OpenEXR 3.1 takes no other compression for deep parts.
        Imf::Compression named;
        int level = -1;
        if (detail::exrCompression(spec.get_string_attribute("compression"), named, level) &&
            named == Imf::ZIPS_COMPRESSION && level > 0)
            header.zipCompressionLevel() = level;
        for (int c = 0; c < spec.nchannels; ++c)
            header.channels().insert(spec.channelnames[size_t(c)],
                                     Imf::Channel(pixelType(spec.channelformat(c))));
        m_impl = std::make_unique<Impl>();
        m_impl->spec = spec;
        // Line blocks compressed in parallel, as flat files are (flat_exr.cpp).
        const int threads = detail::exrThreads();
        if (Imf::globalThreadCount() != threads) Imf::setGlobalThreadCount(threads);
        m_impl->file = std::make_unique<Imf::DeepScanLineOutputFile>(path.c_str(), header, threads);
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        m_impl.reset();
        return false;
    }
}

bool DeepScanlineWriter::write(int ybegin, int yend, const OIIO::DeepData& samples,
                               std::string& error) {
    if (!m_impl) {
        error = "not open";
        return false;
    }
    try {
        std::vector<unsigned> counts(samples.all_samples().begin(), samples.all_samples().end());
        std::vector<OIIO::TypeDesc> types;
        for (int c = 0; c < samples.channels(); ++c)
            types.push_back(samples.channeltype(c));
        samples.get_pointers(m_impl->pointers);
        const Imf::DeepFrameBuffer fb = frameBuffer(m_impl->spec, ybegin, counts.data(), types,
                                                    m_impl->pointers, samples.samplesize());
        m_impl->file->setFrameBuffer(fb);
        m_impl->file->writePixels(yend - ybegin);
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

bool DeepScanlineWriter::close(std::string& error) {
    try {
        if (m_impl) m_impl->file.reset();
        m_impl.reset();
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

} // namespace dhdr
