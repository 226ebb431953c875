#include <Imath/half.h>
#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/io/deep_exr.h>
#include <dhdr/io/exr_header.h>
#include <memory>
#include <numeric>

namespace dhdr {

struct DeepGBufferReader::File {
    std::unique_ptr<OIIO::ImageInput> in;
    DeepScanlineReader scanlines; // OpenEXR's own reader (deep_exr.h)
    OIIO::ImageSpec spec;         // as in the file
    int subimage = 0;
    std::vector<int> source; // where each channel held in memory comes from (−1: not there)
    OIIO::DeepData whole;    // a tiled file, read once
    bool haveWhole = false;

    // The deep pixels of rows [ybegin, yend): `band` read from a scanline file, or a tiled
    // file's whole image with `skip` pixels before the band's first; null with `error`.
    const OIIO::DeepData* rows(int ybegin, int yend, OIIO::DeepData& band, size_t& skip,
                               std::string& error) {
        if (spec.tile_width == 0)
            return scanlines.read(ybegin, yend, band, error) ? &band : nullptr;
        if (!haveWhole) {
            if (!in->read_native_deep_image(subimage, 0, whole)) {
                error = in->geterror();
                if (error.empty()) error = "cannot read its deep pixels";
                return nullptr;
            }
            haveWhole = true;
        }
        skip = size_t(ybegin - spec.y) * size_t(spec.width);
        return &whole;
    }
};

namespace {

// A band's deep samples read in place: each sample's channels lie together in the DeepData,
// at fixed offsets from its first byte, read there rather than with one deep_value call (and
// type switch) each; the channels' types looked up once (DeepData::channeltype is a call).
class DeepSamples {
public:
    // `npix` pixels from pixel `skip` of `deep`, which has `nchannels` channels.
    DeepSamples(const OIIO::DeepData& deep, size_t skip, size_t npix, int nchannels)
        : m_deep(deep), m_skip(skip), m_sampleBytes(deep.samplesize()),
          m_offset(size_t(nchannels), 0), m_type(size_t(nchannels), Type::Other) {
        for (int c = 0; c < nchannels; ++c) {
            const OIIO::TypeDesc t = deep.channeltype(c);
            m_type[size_t(c)] = t == OIIO::TypeDesc::FLOAT  ? Type::Float
                                : t == OIIO::TypeDesc::HALF ? Type::Half
                                : t == OIIO::TypeDesc::UINT ? Type::Uint
                                                            : Type::Other;
        }
        for (size_t p = 0; p < npix; ++p) {
            if (count(p) == 0) continue;
            const char* base = first(p);
            for (int c = 0; c < nchannels; ++c)
                m_offset[size_t(c)] =
                    static_cast<const char*>(deep.data_ptr(int64_t(skip + p), c, 0)) - base;
            break;
        }
    }

    int count(size_t p) const { return m_deep.samples(int64_t(m_skip + p)); }
    // Sample s of pixel p, as its first byte.
    const char* sample(size_t p, int s) const { return first(p) + size_t(s) * m_sampleBytes; }

    float value(const char* sample, int c) const {
        const char* at = sample + m_offset[size_t(c)];
        switch (m_type[size_t(c)]) {
        case Type::Float: {
            float v;
            std::memcpy(&v, at, sizeof v);
            return v;
        }
        case Type::Half: {
            Imath::half h;
            std::memcpy(&h, at, sizeof h);
            return float(h);
        }
        case Type::Uint: {
            std::uint32_t u;
            std::memcpy(&u, at, sizeof u);
            return float(u);
        }
        case Type::Other:
            break;
        }
        return 0.0f;
    }

private:
    const char* first(size_t p) const {
        return static_cast<const char*>(m_deep.data_ptr(int64_t(m_skip + p), 0, 0));
    }

    enum class Type { Float, Half, Uint, Other };
    const OIIO::DeepData& m_deep;
    size_t m_skip, m_sampleBytes;
    std::vector<std::ptrdiff_t> m_offset;
    std::vector<Type> m_type;
};

// What is wrong with pixel p's samples for dhdr (channels zFile, zBackFile of the file; −1:
// no ZBack), or null.
const char* sampleProblem(const DeepSamples& d, size_t p, int zFile, int zBackFile) {
    for (int s = 0, n = d.count(p); s < n; ++s) {
        const float z = d.value(d.sample(p, s), zFile);
        const float zBack = zBackFile >= 0 ? d.value(d.sample(p, s), zBackFile) : z;
        if (!std::isfinite(z)) return " has a sample without a finite Z";
        if (zBack > z)
            return " has a volume sample (ZBack > Z); dhdr lights surfaces, whose samples are "
                   "points (ZBack = Z)";
    }
    return nullptr;
}

// Pixel p's samples front to back (by channel zFile, the file's order among equals).
void depthOrder(const DeepSamples& d, size_t p, int zFile, std::vector<int>& order) {
    const int n = d.count(p);
    order.resize(size_t(n));
    std::iota(order.begin(), order.end(), 0);
    if (n > 1)
        std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
            return d.value(d.sample(p, a), zFile) < d.value(d.sample(p, b), zFile);
        });
}

// Pixel p's samples in `order` into `values` (nch channels each, channel c from the file's
// source[c]); returns how many values were not finite and became 0.
long long copySamples(const DeepSamples& d, size_t p, const std::vector<int>& order,
                      const std::vector<int>& source, int nch, float* values) {
    long long fixed = 0;
    for (size_t k = 0; k < order.size(); ++k) {
        float* v = values + k * size_t(nch);
        const char* from = d.sample(p, order[k]);
        for (int c = 0; c < nch; ++c) {
            const int f = source[size_t(c)];
            v[c] = f >= 0 ? d.value(from, f) : (c == 2 ? v[1] : 0.0f); // ZBack defaults to Z
            if (!std::isfinite(v[c])) {
                v[c] = 0.0f;
                ++fixed;
            }
        }
    }
    return fixed;
}

} // namespace

DeepGBufferReader::DeepGBufferReader() = default;
DeepGBufferReader::~DeepGBufferReader() = default;

bool DeepGBufferReader::open(const std::string& path, int subimage, std::string& error) {
    m_file = std::make_unique<File>();
    if (!detail::exrHeadersFit(path, error)) return false;
    m_file->in = OIIO::ImageInput::open(path);
    if (!m_file->in) {
        error = OIIO::geterror();
        return false;
    }
    if (!m_file->in->seek_subimage(subimage, 0)) {
        error = "no part " + std::to_string(subimage);
        return false;
    }
    const OIIO::ImageSpec& file = m_file->spec = m_file->in->spec();
    m_file->subimage = subimage;
    if (!file.deep) {
        error = "not a deep image";
        return false;
    }
    gbuffer::Layout layout;
    std::string missing;
    if (!gbuffer::findLayout(file, layout, missing)) {
        error = "no channel '" + missing + "' — is this a G-buffer?";
        return false;
    }
    // The WhenUsed channels the file has (occlusion, the dielectric's, the coat's) are kept.
    unsigned uses = 0;
    for (const gbuffer::ContractChannel& c : gbuffer::kContract)
        if (c.use != 0 && file.channelindex(c.names[0]) >= 0) uses |= c.use;
    const std::vector<std::string> names = gbuffer::deepChannelNames(uses);
    m_file->source.assign(names.size(), -1);
    for (size_t c = 0; c < names.size(); ++c)
        m_file->source[c] = file.channelindex(names[c]);
    if (file.tile_width == 0 && !m_file->scanlines.open(path, subimage, file, error)) return false;
    m_spec = file;
    m_spec.deep = false;
    m_spec.nchannels = int(names.size());
    m_spec.channelnames = names;
    m_spec.set_format(OIIO::TypeDesc::FLOAT);
    m_spec.channelformats.clear();
    m_spec.alpha_channel = 0;
    m_spec.z_channel = 1;
    return true;
}

bool DeepGBufferReader::read(int ybegin, int yend, DeepGBuffer& out, std::string& error,
                             long long* replaced) {
    if (!m_file || !m_file->in) {
        error = "not open";
        return false;
    }
    const OIIO::ImageSpec& file = m_file->spec;
    ybegin = std::max(ybegin, file.y);
    yend = std::min(yend, file.y + file.height);
    if (yend <= ybegin) {
        error = "no rows to read";
        return false;
    }
    const int nch = m_spec.nchannels;
    const std::vector<int>& source = m_file->source;
    OIIO::DeepData band;
    size_t skip = 0;
    const OIIO::DeepData* deep = m_file->rows(ybegin, yend, band, skip, error);
    if (!deep) return false;
    out.spec = m_spec;
    out.spec.y = ybegin;
    out.spec.height = yend - ybegin;
    const size_t npix = size_t(file.width) * size_t(yend - ybegin);
    const DeepSamples samples(*deep, skip, npix, file.nchannels);
    out.first.assign(npix + 1, 0);
    for (size_t p = 0; p < npix; ++p)
        out.first[p + 1] = out.first[p] + std::uint32_t(samples.count(p));
    out.values.assign(size_t(out.first.back()) * size_t(nch), 0.0f);
    const int zFile = source[1], zBackFile = source[2];
    for (size_t p = 0; p < npix; ++p) {
        if (samples.count(p) == 0) continue;
        if (const char* problem = sampleProblem(samples, p, zFile, zBackFile)) {
            error = "pixel (" + std::to_string(file.x + int(p % size_t(file.width))) + ", " +
                    std::to_string(ybegin + int(p / size_t(file.width))) + ")" + problem;
            return false;
        }
    }
    // Each pixel's samples apart, so rows go on every thread with the same values.
    std::atomic<long long> fixed{0};
    parallelBands(0, int64_t(npix), 0, [&](int64_t begin, int64_t end) {
        std::vector<int> order;
        long long local = 0;
        for (size_t p = size_t(begin); p < size_t(end); ++p) {
            if (samples.count(p) == 0) continue;
            depthOrder(samples, p, zFile, order);
            local += copySamples(samples, p, order, source, nch,
                                 &out.values[size_t(out.first[p]) * size_t(nch)]);
        }
        fixed += local;
    });
    if (replaced) *replaced += fixed;
    return true;
}

bool readDeepGBuffer(const std::string& path, int subimage, DeepGBuffer& out, std::string& error,
                     long long* replaced) {
    DeepGBufferReader reader;
    if (!reader.open(path, subimage, error)) return false;
    const OIIO::ImageSpec& spec = reader.spec();
    return reader.read(spec.y, spec.y + spec.height, out, error, replaced);
}

void toDeepData(const DeepGBuffer& g, int ybegin, int yend, OIIO::DeepData& out,
                std::vector<OIIO::TypeDesc> formats) {
    const OIIO::ImageSpec& spec = g.spec;
    const int nch = spec.nchannels;
    if (formats.empty()) formats = gbuffer::channelFormats(spec.channelnames);
    const size_t firstPixel = size_t(ybegin - spec.y) * size_t(spec.width);
    const size_t npix = size_t(yend - ybegin) * size_t(spec.width);
    out.init(int64_t(npix), nch, formats, spec.channelnames);
    std::vector<unsigned> counts(npix);
    for (size_t p = 0; p < npix; ++p)
        counts[p] = g.first[firstPixel + p + 1] - g.first[firstPixel + p];
    out.set_all_samples(counts);
    // Each pixel's samples are stored together, channel c of sample s at the channel's offset
    // + s × samplesize(): filled through one pointer a pixel rather than a call a value, in the
    // conversions set_deep_value makes (half rounded to nearest even, ids as integers).
    std::vector<size_t> offsets; // each channel's bytes into a sample, the same in every pixel
    const size_t stride = out.samplesize();
    for (size_t p = 0; p < npix; ++p) {
        if (counts[p] == 0) continue;
        auto* pixel = static_cast<std::byte*>(out.data_ptr(int64_t(p), 0, 0));
        for (int c = int(offsets.size()); c < nch; ++c)
            offsets.push_back(
                size_t(static_cast<std::byte*>(out.data_ptr(int64_t(p), c, 0)) - pixel));
        for (unsigned s = 0; s < counts[p]; ++s) {
            const float* v = &g.values[(size_t(g.first[firstPixel + p]) + s) * size_t(nch)];
            std::byte* sample = pixel + size_t(s) * stride;
            for (int c = 0; c < nch; ++c) {
                std::byte* at = sample + offsets[size_t(c)];
                const OIIO::TypeDesc t = formats[size_t(c)];
                if (t == OIIO::TypeDesc::UINT) {
                    const auto u = std::uint32_t(std::max(v[c], 0.0f));
                    std::memcpy(at, &u, sizeof u);
                } else if (t == OIIO::TypeDesc::HALF) {
                    const Imath::half h(v[c]);
                    std::memcpy(at, &h, sizeof h);
                } else {
                    std::memcpy(at, &v[c], sizeof(float));
                }
            }
        }
    }
}

} // namespace dhdr
