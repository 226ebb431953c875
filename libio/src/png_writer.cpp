#include "png_header.h"
#include "temporary_files.h"

#include <OpenImageIO/imageio.h>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <deque>
#include <dhdr/io/png_writer.h>
#include <filesystem>
#include <future>
#include <libdeflate.h>
#include <unistd.h>
#include <vector>
#include <zlib.h>

namespace fs = std::filesystem;

namespace dhdr {

namespace {

// Rows a group holds: about 1 MiB of pixels, so that each deflate call is long enough for
// its first 32 KiB (primed, but fewer matches) not to matter, and a 16K frame holds a few.
constexpr size_t kGroupBytes = size_t(1) << 20;
constexpr size_t kWindow = 32768;
// zlib's level for groups of rows and libdeflate's for whole images: the fastest of each,
// as small as libpng's level 6 on dithered frames (bench/README.md, batch).
constexpr int kZlibLevel = 1;
constexpr int kLibdeflateLevel = 1;
// A chunk's length is at most 2^31 − 1; IDAT data is cut well below that.
constexpr size_t kMaxIdat = size_t(1) << 30;

// One group of rows deflated: a raw deflate stream that a sync flush leaves byte-aligned
// (the last group's ends the stream), primed with `dictionary`, and its Adler-32.
struct Deflated {
    std::unique_ptr<unsigned char[]> bytes; // not zeroed first: frames are tens of MB
    size_t size = 0;
    uLong adler = 1;
    size_t length = 0;
    bool ok = true;
    bool zlib = false; // a whole zlib stream (PngWriteOptions::whole)
    void allocate(size_t n) { bytes.reset(new unsigned char[n]); }
};

Deflated deflateGroup(std::vector<unsigned char> raw, std::vector<unsigned char> dictionary,
                      int level, bool last) {
    Deflated d;
    d.length = raw.size();
    d.adler = adler32_z(1L, raw.data(), raw.size());
    z_stream z{};
    if (deflateInit2(&z, level, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
        d.ok = false;
        return d;
    }
    if (!dictionary.empty()) deflateSetDictionary(&z, dictionary.data(), uInt(dictionary.size()));
    const size_t bound = deflateBound(&z, uLong(raw.size())) + 64;
    d.allocate(bound);
    z.next_in = raw.data();
    z.avail_in = uInt(raw.size());
    z.next_out = d.bytes.get();
    z.avail_out = uInt(bound);
    const int status = deflate(&z, last ? Z_FINISH : Z_SYNC_FLUSH);
    d.ok = last ? status == Z_STREAM_END : status == Z_OK && z.avail_in == 0;
    d.size = z.total_out;
    deflateEnd(&z);
    return d;
}

} // namespace

struct PngFileWriter::Impl {
    std::string temporary;
    FILE* file = nullptr;
    PngWriteOptions options;
    int width = 0, height = 0, channels = 0, bytesPerValue = 1, alpha = -1;
    size_t rowBytes = 0; // filter byte included
    int nextRow = 0, groupRows = 1;
    std::vector<unsigned char> group, previousTail;
    std::deque<std::future<Deflated>> pending;
    uLong adler = 1;
    bool headerWritten = false;

    bool put(const void* data, size_t size) { return std::fwrite(data, 1, size, file) == size; }
    // IDAT chunks of `head`, `size` bytes of `body` and `tail`, written as they are.
    bool putIdat(const std::string& head, const unsigned char* body, size_t size,
                 const std::string& tail) {
        if (head.size() + size + tail.size() > kMaxIdat) {
            // Only a frame deflated whole gets here (past 1 GiB): one piece at a time.
            for (size_t at = 0; at < size; at += kMaxIdat)
                if (!putIdat(at == 0 ? head : "", body + at, std::min(kMaxIdat, size - at), ""))
                    return false;
            return putIdat(tail, nullptr, 0, "");
        }
        unsigned char length[4];
        const uint32_t n = uint32_t(head.size() + size + tail.size());
        for (int i = 0; i < 4; ++i)
            length[i] = static_cast<unsigned char>(n >> (24 - 8 * i));
        uLong crc = crc32_z(0L, reinterpret_cast<const Bytef*>("IDAT"), 4);
        crc = crc32_z(crc, reinterpret_cast<const Bytef*>(head.data()), head.size());
        crc = crc32_z(crc, body, size);
        crc = crc32_z(crc, reinterpret_cast<const Bytef*>(tail.data()), tail.size());
        unsigned char check[4];
        for (int i = 0; i < 4; ++i)
            check[i] = static_cast<unsigned char>(crc >> (24 - 8 * i));
        return put(length, 4) && put("IDAT", 4) && put(head.data(), head.size()) &&
               put(body, size) && put(tail.data(), tail.size()) && put(check, 4);
    }
    // Writes the oldest group deflated: the zlib header before the first, the Adler-32 of
    // every row after the last.
    bool writeOldest() {
        Deflated d = pending.front().get();
        pending.pop_front();
        if (!d.ok) return false;
        if (d.zlib) return putIdat("", d.bytes.get(), d.size, "");
        adler = adler32_combine(adler, d.adler, z_off_t(d.length));
        const std::string head = headerWritten ? "" : zlibHeader();
        headerWritten = true;
        std::string tail;
        if (nextRow == height && pending.empty())
            for (int shift = 24; shift >= 0; shift -= 8)
                tail += char((adler >> shift) & 0xff);
        return putIdat(head, d.bytes.get(), d.size, tail);
    }
    std::string zlibHeader() const {
        // CMF: deflate, 32 KiB window; FLG: FLEVEL 0 ("fastest", kZlibLevel), check bits.
        int flg = 0;
        flg += (31 - (0x78 * 256 + flg) % 31) % 31;
        return {char(0x78), char(flg)};
    }
    // Hands the rows gathered to a thread (or deflates them here), keeping at most
    // `nthreads` groups in flight so that memory stays a few groups.
    bool flushGroup() {
        const bool last = nextRow == height;
        std::vector<unsigned char> dictionary = previousTail;
        const size_t keep = std::min(kWindow, group.size());
        previousTail.assign(group.end() - std::ptrdiff_t(keep), group.end());
        if (options.nthreads <= 1) {
            std::promise<Deflated> done;
            done.set_value(deflateGroup(std::move(group), std::move(dictionary), kZlibLevel, last));
            pending.push_back(done.get_future());
        } else {
            pending.push_back(std::async(std::launch::async, deflateGroup, std::move(group),
                                         std::move(dictionary), kZlibLevel, last));
        }
        group.clear();
        while (!pending.empty() && (last || pending.size() >= size_t(options.nthreads)))
            if (!writeOldest()) return false;
        return true;
    }
    // The whole image as one zlib stream, by libdeflate: twice as fast as zlib's level 1
    // and as small, but it can only end a stream, not flush one (bench/README.md, batch).
    bool deflateWhole() {
        libdeflate_compressor* c = libdeflate_alloc_compressor(kLibdeflateLevel);
        if (!c) return false;
        Deflated d;
        d.zlib = true;
        const size_t bound = libdeflate_zlib_compress_bound(c, group.size());
        d.allocate(bound);
        const size_t n =
            libdeflate_zlib_compress(c, group.data(), group.size(), d.bytes.get(), bound);
        libdeflate_free_compressor(c);
        d.size = n;
        std::promise<Deflated> done;
        done.set_value(std::move(d));
        pending.push_back(done.get_future());
        return n > 0 && writeOldest();
    }
    void addRow(const unsigned char* row) {
        const size_t at = group.size();
        group.push_back(0); // filter type None
        group.insert(group.end(), row, row + rowBytes - 1);
        unsigned char* values = group.data() + at + 1;
        if (bytesPerValue == 1) {
            if (alpha >= 0) detail::pngDeassociate(values, size_t(width), channels, alpha);
            return;
        }
        // Native 16-bit values to PNG's big-endian, after the division as OIIO orders them.
        std::vector<uint16_t> v(size_t(width) * size_t(channels));
        std::memcpy(v.data(), values, v.size() * 2);
        if (alpha >= 0) detail::pngDeassociate(v.data(), size_t(width), channels, alpha);
        for (size_t i = 0; i < v.size(); ++i) {
            values[2 * i] = static_cast<unsigned char>(v[i] >> 8);
            values[2 * i + 1] = static_cast<unsigned char>(v[i]);
        }
    }
};

PngFileWriter::PngFileWriter(std::string path) : m_path(std::move(path)) {}

PngFileWriter::~PngFileWriter() {
    if (!m_impl) return;
    for (auto& p : m_impl->pending)
        p.wait();
    if (m_impl->file) std::fclose(m_impl->file);
    if (!m_impl->temporary.empty()) {
        std::error_code ec;
        fs::remove(m_impl->temporary, ec);
        detail::unregisterTemporary(m_impl->temporary);
    }
}

bool PngFileWriter::handles(const OIIO::ImageSpec& spec) {
    // libpng's PNG_FILTER_NONE (8): rows unfiltered, as here. Without it libpng chooses a
    // filter per row, which undithered pixels gain from (docs/tonemap.md): left to it.
    const int filter = spec.get_int_attribute("png:filter", 0);
    return (spec.format == OIIO::TypeDesc::UINT8 || spec.format == OIIO::TypeDesc::UINT16) &&
           spec.channelformats.empty() && spec.nchannels >= 1 && spec.nchannels <= 4 &&
           spec.width > 0 && spec.height > 0 && spec.depth <= 1 && filter == 8 &&
           (detail::pngAlphaChannel(spec) < 0 || detail::pngAlphaGamma(spec) == 1.0f);
}

bool PngFileWriter::open(const OIIO::ImageSpec& spec, const PngWriteOptions& options) {
    if (!handles(spec)) {
        m_error = m_path + ": cannot write this image as PNG here (OpenImageIO's writer can)";
        return false;
    }
    std::string header, why;
    if (!detail::pngHeader(spec, header, why)) {
        m_error = m_path + ": cannot write: " + why;
        return false;
    }
    m_impl = std::make_unique<Impl>();
    Impl& s = *m_impl;
    s.options = options;
    s.width = spec.width;
    s.height = spec.height;
    s.channels = spec.nchannels;
    s.bytesPerValue = int(spec.format.size());
    s.alpha = detail::pngAlphaChannel(spec);
    s.rowBytes = 1 + size_t(s.width) * size_t(s.channels) * size_t(s.bytesPerValue);
    s.groupRows = int(std::max<size_t>(1, kGroupBytes / s.rowBytes));
    if (s.options.whole) s.group.reserve(s.rowBytes * size_t(s.height));
    const fs::path target(m_path);
    detail::removeStaleTemporaries(target);
    s.temporary = detail::temporaryFor(target, getpid()).string();
    detail::registerTemporary(s.temporary);
    s.file = std::fopen(s.temporary.c_str(), "wb");
    if (!s.file || !s.put(header.data(), header.size())) {
        m_error = m_path + ": cannot write: " + std::strerror(errno);
        return false;
    }
    return true;
}

bool PngFileWriter::writeRows(int ybegin, int yend, const void* pixels) {
    Impl& s = *m_impl;
    if (!s.file || ybegin != s.nextRow || yend < ybegin || yend > s.height) {
        m_error = m_path + ": rows given out of order";
        return false;
    }
    const auto* row = static_cast<const unsigned char*>(pixels);
    for (int y = ybegin; y < yend; ++y, row += s.rowBytes - 1) {
        s.addRow(row);
        ++s.nextRow;
        const bool flush = s.options.whole ? s.nextRow == s.height
                                           : s.nextRow % s.groupRows == 0 || s.nextRow == s.height;
        if (flush && !(s.options.whole ? s.deflateWhole() : s.flushGroup())) {
            m_error = m_path + ": cannot write: " + std::strerror(errno);
            return false;
        }
    }
    return true;
}

bool PngFileWriter::commit() {
    Impl& s = *m_impl;
    if (!s.file || s.nextRow != s.height) {
        m_error =
            m_path + ": cannot write: " + std::to_string(s.height - s.nextRow) + " rows missing";
        return false;
    }
    std::string end;
    detail::appendPngChunk(end, "IEND", "", 0);
    const bool written = s.put(end.data(), end.size());
    const bool closed = std::fclose(s.file) == 0;
    s.file = nullptr;
    if (!written || !closed) {
        m_error = m_path + ": cannot write: " + std::strerror(errno);
        return false;
    }
    std::error_code ec;
    fs::rename(s.temporary, m_path, ec);
    if (ec) {
        m_error = m_path + ": cannot move the output into place: " + ec.message();
        return false;
    }
    detail::unregisterTemporary(s.temporary);
    s.temporary.clear();
    return true;
}

} // namespace dhdr
