#include "exr_spec_header.h"
#include "flat_exr.h"
#include "native_pixels.h"
#include "temporary_files.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <dhdr/io/deep_exr.h>
#include <dhdr/io/errors.h>
#include <dhdr/io/image_output.h>
#include <filesystem>
#include <unistd.h>

namespace fs = std::filesystem;

namespace dhdr {

ImageFileOutput::ImageFileOutput(std::string path, ImageOutputOptions options)
    : m_path(std::move(path)), m_options(std::move(options)) {
    const fs::path target(m_path);
    detail::removeStaleTemporaries(target);
    // Frames of a sequence written at once by one process have different targets, so the
    // process id keeps temporaries apart.
    m_temporary = detail::temporaryFor(target, getpid()).string();
}

ImageFileOutput::~ImageFileOutput() {
    if (m_committed) return;
    if (m_out) m_out->close();
    m_deep.reset();
    m_flat.reset();
    std::error_code ec;
    fs::remove(m_temporary, ec);
    detail::unregisterTemporary(m_temporary);
}

bool ImageFileOutput::fail(const std::string& message) {
    m_error = m_path + ": " + message;
    return false;
}

std::string ImageFileOutput::geterror(bool clear) const {
    std::string e = m_error;
    if (clear) m_error.clear();
    return e;
}

const OIIO::ImageSpec& ImageFileOutput::spec() const {
    static const OIIO::ImageSpec none;
    return m_out ? m_out->spec() : (m_deep || m_flat) ? m_ownSpec : none;
}

bool ImageFileOutput::open(OIIO::ImageSpec spec, const std::vector<OIIO::TypeDesc>& formats) {
    m_out = OIIO::ImageOutput::create(m_path);
    if (!m_out) return fail("cannot write this format: " + oneLine(OIIO::geterror()));
    if (formats.size() == size_t(spec.nchannels) && formats.size() > 1 &&
        m_out->supports("channelformats")) {
        spec.channelformats = formats;
    } else {
        spec.set_format(formats.empty() ? OIIO::TypeDesc::FLOAT : formats[0]);
        spec.channelformats.clear();
    }
    if (!m_options.software.empty()) spec.attribute("Software", m_options.software);
    if (!m_options.compression.empty()) spec.attribute("compression", m_options.compression);
    // Scanline output whatever the input was (a tiled input's spec carries its tiling, which
    // the scanline writes below cannot fill), one part, flat.
    spec.tile_width = spec.tile_height = spec.tile_depth = 0;
    spec.deep = false;
    spec.erase_attribute("oiio:subimages");
    bool native = true;
    for (int c = 0; c < spec.nchannels; ++c) {
        const OIIO::TypeDesc t = spec.channelformat(c);
        native = native && (t == OIIO::TypeDesc::HALF || t == OIIO::TypeDesc::FLOAT ||
                            t == OIIO::TypeDesc::UINT);
    }
    const int z = spec.channelindex("Z");
    m_native = native ? std::make_unique<NativeWriter>(spec, z) : nullptr;
    std::string why;
    if (native && m_options.throughOpenExr && spec.nchannels > 0 &&
        detail::exrHeaderKeepsEverything(spec, why)) {
        std::string ext = fs::path(m_path).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
        Imf::Compression known;
        int level;
        const std::string compression = spec.get_string_attribute("compression");
        if (ext == ".exr" &&
            (compression.empty() || detail::exrCompression(compression, known, level))) {
            m_out.reset();
            return openFlatExr(spec);
        }
    }
    return openTemporary(spec);
}

bool ImageFileOutput::openFlatExr(const OIIO::ImageSpec& spec) {
    detail::registerTemporary(m_temporary);
    m_flat = std::make_unique<detail::FlatScanlineWriter>();
    if (std::string error;
        !m_flat->open(m_temporary, spec, spec.get_string_attribute("compression"), error)) {
        m_flat.reset();
        return fail("cannot write: " + oneLine(error));
    }
    m_ownSpec = spec;
    return true;
}

bool ImageFileOutput::openTemporary(const OIIO::ImageSpec& spec) {
    detail::registerTemporary(m_temporary);
    if (!m_out->open(m_temporary, spec)) {
        const std::string e = oneLine(m_out->geterror());
        m_out.reset();
        return fail("cannot write: " + e);
    }
    return true;
}

bool ImageFileOutput::openDeep(OIIO::ImageSpec spec) {
    std::string ext = fs::path(m_path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext != ".exr") return fail("cannot write deep images in this format (use .exr)");
    if (!m_options.software.empty()) spec.attribute("Software", m_options.software);
    if (!m_options.compression.empty()) spec.attribute("compression", m_options.compression);
    spec.tile_width = spec.tile_height = spec.tile_depth = 0;
    spec.deep = true;
    detail::registerTemporary(m_temporary);
    m_deep = std::make_unique<DeepScanlineWriter>();
    if (std::string error; !m_deep->open(m_temporary, spec, error)) {
        m_deep.reset();
        return fail("cannot write: " + oneLine(error));
    }
    m_ownSpec = spec;
    return true;
}

namespace {

// Whether any sample of `samples` holds NaN or ±Inf, read a pixel at a time through its
// pointer (DeepData's per-value calls cost a deep G-buffer's write a fifth of its time).
bool anyNonFinite(const OIIO::DeepData& samples) {
    const size_t stride = samples.samplesize();
    std::vector<size_t> offsets; // each channel's bytes into a sample, the same in every pixel
    std::vector<OIIO::TypeDesc> types;
    for (int c = 0; c < samples.channels(); ++c)
        types.push_back(samples.channeltype(c));
    for (int64_t p = 0; p < samples.pixels(); ++p) {
        const int n = samples.samples(p);
        if (n == 0) continue;
        const auto* pixel = static_cast<const std::byte*>(samples.data_ptr(p, 0, 0));
        for (int c = int(offsets.size()); c < samples.channels(); ++c)
            offsets.push_back(
                size_t(static_cast<const std::byte*>(samples.data_ptr(p, c, 0)) - pixel));
        for (int c = 0; c < samples.channels(); ++c) {
            const OIIO::TypeDesc t = types[size_t(c)];
            const std::byte* at = pixel + offsets[size_t(c)];
            for (int k = 0; k < n; ++k, at += stride) {
                if (t == OIIO::TypeDesc::HALF) {
                    std::uint16_t bits;
                    std::memcpy(&bits, at, sizeof bits);
                    if ((bits & 0x7c00u) == 0x7c00u) return true; // exponent all ones
                } else if (t == OIIO::TypeDesc::FLOAT) {
                    float v;
                    std::memcpy(&v, at, sizeof v);
                    if (!std::isfinite(v)) return true;
                } else if (t != OIIO::TypeDesc::UINT &&
                           !std::isfinite(samples.deep_value(p, c, k))) {
                    return true;
                }
            }
        }
    }
    return false;
}

} // namespace

bool ImageFileOutput::writeDeepRows(int ybegin, int yend, const OIIO::DeepData& samples) {
    // The flat output's rule for every sample: NaN becomes 0, ±Inf (a half channel's overflow
    // included, when the value was stored) the type's largest finite value, counted.
    std::unique_ptr<OIIO::DeepData> fixed;
    if (anyNonFinite(samples))
        for (int64_t p = 0; p < samples.pixels(); ++p)
            for (int c = 0; c < samples.channels(); ++c)
                for (int k = 0; k < samples.samples(p); ++k) {
                    const float v = samples.deep_value(p, c, k);
                    if (std::isfinite(v)) continue;
                    if (!fixed) fixed = std::make_unique<OIIO::DeepData>(samples);
                    const float largest =
                        samples.channeltype(c) == OIIO::TypeDesc::HALF ? 65504.0f : FLT_MAX;
                    fixed->set_deep_value(p, c, k,
                                          std::isnan(v) ? 0.0f : std::copysign(largest, v));
                    ++(std::isnan(v) ? m_nonFinite : m_clamped);
                }
    if (std::string error; !m_deep->write(ybegin, yend, fixed ? *fixed : samples, error))
        return fail("cannot write: " + oneLine(error));
    return true;
}

bool ImageFileOutput::writeRows(int ybegin, int yend, const float* pixels) {
    const OIIO::ImageSpec& spec = this->spec();
    const size_t count = size_t(yend - ybegin) * size_t(spec.width);
    bool written = false;
    if (m_native) {
        // In the file's own types, so that uint channels hold integers rather than OIIO's
        // float-to-uint scaling of [0, 1] to [0, 2^32 − 1].
        m_buffer.resize(count * m_native->pixelBytes());
        m_native->convert(pixels, count, m_buffer.data(), m_clamped, m_nonFinite);
        if (m_flat) {
            std::string error;
            return m_flat->write(ybegin, yend, m_buffer.data(), error) ||
                   fail("cannot write: " + oneLine(error));
        }
        written = m_out->write_scanlines(ybegin, yend, 0, OIIO::TypeUnknown, m_buffer.data());
    } else {
        // Integer formats: OIIO's conversion clamps to their range; NaN only needs replacing.
        m_floats.assign(pixels, pixels + count * size_t(spec.nchannels));
        for (float& v : m_floats)
            if (std::isnan(v)) {
                v = 0.0f;
                ++m_nonFinite;
            }
        written = m_out->write_scanlines(ybegin, yend, 0, OIIO::TypeDesc::FLOAT, m_floats.data());
    }
    return written || fail("cannot write: " + oneLine(m_out->geterror()));
}

bool ImageFileOutput::writeRows(const OIIO::ImageBuf& image, OIIO::ROI rows) {
    const OIIO::ImageSpec& spec = this->spec();
    const OIIO::ImageSpec& src = image.spec();
    // Float for OpenEXR's own writer, which takes only the file's types by way of the native
    // conversion.
    const OIIO::TypeDesc type = m_flat ? OIIO::TypeDesc::FLOAT : src.format;
    rows.xbegin = spec.x;
    rows.xend = spec.x + spec.width;
    rows.chbegin = 0;
    rows.chend = spec.nchannels;
    // Straight from the buffer when it holds exactly the file's rows and channels, side by
    // side; else copied out.
    const bool direct = image.localpixels() && src.format == type && src.x == spec.x &&
                        src.width == spec.width && src.nchannels == spec.nchannels &&
                        src.channelformats.empty() && rows.ybegin >= src.y &&
                        rows.yend <= src.y + src.height;
    const void* pixels = direct ? image.pixeladdr(spec.x, rows.ybegin) : nullptr;
    std::vector<std::byte> copy;
    if (!direct) {
        copy.resize(rows.npixels() * size_t(spec.nchannels) * type.size());
        if (!image.get_pixels(rows, type, copy.data()))
            return fail("cannot write: " + oneLine(image.geterror()));
        pixels = copy.data();
    }
    if (type == OIIO::TypeDesc::FLOAT)
        return writeRows(rows.ybegin, rows.yend, static_cast<const float*>(pixels));
    // Integer pixels (a display image quantized by the caller) have nothing to sanitize.
    return m_out->write_scanlines(rows.ybegin, rows.yend, 0, type, pixels) ||
           fail("cannot write: " + oneLine(m_out->geterror()));
}

bool ImageFileOutput::commit() {
    if (m_deep) {
        if (std::string error; !m_deep->close(error))
            return fail("cannot write: " + oneLine(error));
        m_deep.reset();
    } else if (m_flat) {
        if (std::string error; !m_flat->close(error))
            return fail("cannot write: " + oneLine(error));
        m_flat.reset();
    } else if (!m_out) {
        return fail("cannot write: the file was never opened");
    } else if (!m_out->close()) {
        return fail("cannot write: " + oneLine(m_out->geterror()));
    }
    m_out.reset();
    std::error_code ec;
    fs::rename(m_temporary, m_path, ec);
    if (ec) return fail("cannot move the output into place: " + ec.message());
    m_committed = true;
    detail::unregisterTemporary(m_temporary);
    return true;
}

std::vector<std::string> ImageFileOutput::warnings() const {
    std::vector<std::string> lines;
    if (m_nonFinite > 0)
        lines.push_back(m_path + ": wrote " + std::to_string(m_nonFinite) +
                        " non-finite values as finite ones (NaN → 0, ±Inf → the largest float)");
    if (m_clamped > 0)
        lines.push_back(m_path + ": " + std::to_string(m_clamped) +
                        " values beyond half float's ±65504 were clamped to it; write float to "
                        "keep them (dhdr-light --type float)");
    return lines;
}

bool writeFileAtomically(const std::string& path,
                         const std::function<bool(const std::string&, std::string&)>& write,
                         std::string& error) {
    const fs::path target(path);
    detail::removeStaleTemporaries(target);
    const fs::path temporary = detail::temporaryFor(target, getpid());
    detail::registerTemporary(temporary.string());
    std::error_code ec;
    std::string why;
    if (!write(temporary.string(), why)) {
        fs::remove(temporary, ec);
        detail::unregisterTemporary(temporary.string());
        error = path + ": cannot write" + (why.empty() ? "" : ": " + why);
        return false;
    }
    fs::rename(temporary, target, ec);
    detail::unregisterTemporary(temporary.string());
    if (ec) {
        fs::remove(temporary, ec);
        error = path + ": cannot move the output into place: " + ec.message();
        return false;
    }
    return true;
}

void removeTemporaryOutputsOnSignals() {
    detail::installTemporaryHandlers();
}

} // namespace dhdr
