#include "native_pixels.h"

#include <OpenImageIO/deepdata.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <dhdr/io/banded_read.h>
#include <dhdr/io/deep_exr.h>
#include <dhdr/io/pixel_limit.h>
#include <dhdr/io/strip_reader.h>
#include <mutex>
#include <thread>

namespace dhdr {

namespace {

// Deep pixels flat: each pixel of `deep` its front sample (the smallest Z), or zero with
// Z = +∞ where it has none (a G-buffer's background); `out` holds channels [chbegin, chend).
void flattenFrontSamples(const OIIO::DeepData& deep, int z, int chbegin, int chend, float* out) {
    const size_t nch = size_t(chend - chbegin);
    for (int64_t p = 0, n = deep.pixels(); p < n; ++p) {
        float* o = out + size_t(p) * nch;
        int front = -1;
        for (int k = 0; k < deep.samples(p); ++k)
            if (front < 0 || (z >= 0 && deep.deep_value(p, z, k) < deep.deep_value(p, z, front)))
                front = k;
        for (int c = chbegin; c < chend; ++c) {
            float v = c == z ? INFINITY : 0.0f;
            if (front >= 0)
                v = deep.channeltype(c) == OIIO::TypeDesc::UINT
                        ? float(deep.deep_value_uint(p, c, front))
                        : deep.deep_value(p, c, front);
            o[c - chbegin] = v;
        }
    }
}

} // namespace

bool StripReader::open(const std::string& path, int subimage, int chbegin, int chend, int nthreads,
                       std::string& error, bool frontSamples) {
    m_whole.reset();
    m_deep.reset();
    if (auto probe = frontSamples ? OIIO::ImageInput::open(path) : nullptr;
        probe && probe->seek_subimage(subimage, 0) && probe->spec().deep) {
        const OIIO::ImageSpec& file = probe->spec();
        if (std::string e = pixelLimitError(file.width, file.height, file.depth); !e.empty()) {
            error = std::move(e);
            return false;
        }
        m_chbegin = std::clamp(chbegin, 0, file.nchannels);
        m_chend = std::clamp(chend, m_chbegin, file.nchannels);
        m_subimage = subimage;
        m_spec = floatChannelSpec(file, m_chbegin, m_chend);
        m_spec.deep = false;
        if (file.tile_width == 0) {
            // Scanlines: each strip's rows are read (through OpenEXR itself, deep_exr.h) and
            // flattened when asked for.
            m_deep = std::make_unique<DeepScanlineReader>();
            m_deepSpec = file;
            return m_deep->open(path, subimage, file, error);
        }
        // Tiled: read whole once and served from memory.
        OIIO::DeepData deep;
        if (!probe->read_native_deep_image(subimage, 0, deep)) {
            error = probe->geterror();
            if (error.empty()) error = "cannot read its deep pixels";
            return false;
        }
        m_whole.reset(m_spec, OIIO::InitializePixels::No);
        flattenFrontSamples(deep, file.channelindex("Z"), m_chbegin, m_chend,
                            static_cast<float*>(m_whole.localpixels()));
        return true;
    }
    m_in = openFlatPart(path, subimage, error);
    if (!m_in) return false;
    const OIIO::ImageSpec file = m_in->spec();
    m_subimage = subimage;
    m_path = path;
    m_workers = nthreads > 0 ? nthreads : int(std::max(1u, std::thread::hardware_concurrency()));
    m_inputs.clear();
    m_native_spec.reset();
    m_chbegin = std::clamp(chbegin, 0, file.nchannels);
    m_chend = std::clamp(chend, m_chbegin, file.nchannels);
    if (std::string(m_in->format_name()) != "openexr" || file.tile_width > 0) {
        // Read whole: what OIIO cannot hand out by scanlines cheaply.
        m_in.reset();
        if (!readBanded(path, m_whole, m_chbegin, m_chend, nthreads, error, subimage)) return false;
        m_spec = m_whole.spec();
        return true;
    }
    m_spec = floatChannelSpec(file, m_chbegin, m_chend);
    return true;
}

bool StripReader::read(int ybegin, int yend, OIIO::ImageBuf& strip, std::string& error,
                       const OIIO::ImageBuf* reuse, int* copiedEnd) {
    ybegin = std::max(ybegin, m_spec.y);
    yend = std::min(yend, m_spec.y + m_spec.height);
    OIIO::ImageSpec rows = m_spec;
    rows.y = ybegin;
    rows.height = std::max(0, yend - ybegin);
    const OIIO::ImageSpec& held = strip.spec();
    if (strip.initialized() && strip.localpixels() && held.format == OIIO::TypeDesc::FLOAT &&
        held.width == rows.width && held.nchannels == rows.nchannels &&
        held.height == rows.height) {
        strip.set_origin(rows.x, rows.y);
    } else {
        strip.reset(rows, OIIO::InitializePixels::No);
        if (!strip.localpixels()) {
            error = "cannot allocate memory for a strip of its pixels";
            return false;
        }
    }
    if (copiedEnd) *copiedEnd = ybegin;
    if (rows.height == 0) return true;
    auto* out = static_cast<float*>(strip.localpixels());
    const size_t rowFloats = size_t(rows.width) * size_t(rows.nchannels);
    // The rows `reuse` holds from ybegin on, copied.
    int copied = ybegin;
    if (reuse && reuse != &strip && reuse->initialized() && reuse->localpixels()) {
        const OIIO::ImageSpec& r = reuse->spec();
        if (r.format == OIIO::TypeDesc::FLOAT && r.channelformats.empty() && r.x == rows.x &&
            r.width == rows.width && r.nchannels == rows.nchannels && r.y <= ybegin &&
            ybegin < r.y + r.height) {
            copied = std::min(yend, r.y + r.height);
            std::memcpy(out, reuse->pixeladdr(rows.x, ybegin),
                        rowFloats * size_t(copied - ybegin) * sizeof(float));
        }
    }
    if (copiedEnd) *copiedEnd = copied;
    if (copied == yend) return true;
    return decode(copied, yend, out + size_t(copied - ybegin) * rowFloats, error);
}

bool StripReader::decode(int ybegin, int yend, float* out, std::string& error) {
    const size_t rowFloats = size_t(m_spec.width) * size_t(m_spec.nchannels);
    if (m_whole.initialized()) {
        std::memcpy(out, m_whole.pixeladdr(m_spec.x, ybegin),
                    rowFloats * size_t(yend - ybegin) * sizeof(float));
        return true;
    }
    if (m_deep) {
        OIIO::DeepData deep;
        if (!m_deep->read(ybegin, yend, deep, error)) return false;
        flattenFrontSamples(deep, m_deepSpec.channelindex("Z"), m_chbegin, m_chend, out);
        return true;
    }
    if (!m_native_spec) m_native_spec = std::make_unique<OIIO::ImageSpec>(m_in->spec());
    const NativeReader native(*m_native_spec, m_chbegin, m_chend);
    const int width = m_spec.width, height = yend - ybegin;
    const size_t rowBytes = size_t(width) * native.bytes;
    m_native.resize(rowBytes * size_t(height));
    // Bands of 16 rows (a ZIP chunk; a multiple of the others' but DWAB's), decoded and
    // converted by as many workers as there are bands, up to the thread count.
    constexpr int kBand = 64;
    const int bands = (height + kBand - 1) / kBand;
    const int workers = std::clamp(m_workers, 1, bands);
    while (int(m_inputs.size()) < workers) {
        std::unique_ptr<OIIO::ImageInput> in =
            m_inputs.empty() ? std::move(m_in) : OIIO::ImageInput::open(m_path);
        if (in && m_subimage != 0 && !in->seek_subimage(m_subimage, 0)) in.reset();
        if (!in) {
            error = "cannot open it again: " + OIIO::geterror();
            return false;
        }
        m_inputs.push_back(std::move(in));
    }
    std::atomic<int> next{0};
    std::atomic<bool> failed{false};
    std::mutex errorMutex;
    auto work = [&](int w) {
        OIIO::ImageInput& in = *m_inputs[size_t(w)];
        for (int b = next++; b < bands && !failed; b = next++) {
            const int y0 = ybegin + b * kBand, y1 = std::min(y0 + kBand, yend);
            std::byte* band = m_native.data() + size_t(y0 - ybegin) * rowBytes;
            if (!in.read_native_scanlines(m_subimage, 0, y0, y1, 0, m_chbegin, m_chend, band) ||
                !native.toFloat(band, out + size_t(y0 - ybegin) * rowFloats, width, y1 - y0)) {
                std::lock_guard<std::mutex> lock(errorMutex);
                if (!failed.exchange(true)) error = in.geterror();
            }
        }
    };
    std::vector<std::thread> helpers;
    for (int w = 1; w < workers; ++w)
        helpers.emplace_back(work, w);
    work(0);
    for (std::thread& t : helpers)
        t.join();
    if (failed && error.empty())
        error = "cannot read rows " + std::to_string(ybegin) + "–" + std::to_string(yend - 1);
    return !failed;
}

} // namespace dhdr
