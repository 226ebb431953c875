#include "float_pixels.h"
#include "rgb_plane.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <dhdr/common/parallel.h>
#include <dhdr/tonemap/bloom.h>

namespace dhdr {

using detail::RgbPlane;

namespace {

// The seed's bright pass: the mean of the 8 neighbours (an 8-tap box, which keeps single
// fireflies from blooming alone), kept where its tone-mapped luminance exceeds the threshold.
// `logAverage` is the full image's, metered as the tone mapper meters it.
RgbPlane brightPass(const RgbPlane& src, double logAverage, const BloomParams& params,
                    int nthreads) {
    const double scale = logAverage > 0.0 ? params.key / logAverage : 0.0;

    RgbPlane out(src.width, src.height);
    OIIO::parallel_for(
        0, src.height,
        [&](int64_t yy) {
            const int y = int(yy);
            for (int x = 0; x < src.width; ++x) {
                float box[3] = {0.0f, 0.0f, 0.0f};
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        if (dx == 0 && dy == 0) continue;
                        const float* p = src.at(std::clamp(x + dx, 0, src.width - 1),
                                                std::clamp(y + dy, 0, src.height - 1));
                        for (int c = 0; c < 3; ++c)
                            box[c] += p[c] / 8.0f;
                    }
                const double L = scale * luminance(box[0], box[1], box[2], params.metering.weights);
                if (L / (1.0 + L) > double(params.threshold)) std::copy(box, box + 3, out.at(x, y));
            }
        },
        perItem(nthreads));
    return out;
}

} // namespace

struct BloomBuilder::Impl {
    OIIO::ROI frame;
    BloomParams params;
    int nthreads = 0;
    int nextRow = 0;
    LuminanceAccumulator metering;
    // The seed's quarter-size copy, filled as rows arrive.
    detail::BoxDownsampler quarter;
    std::vector<float> rgb; // one row's R, G, B
    RgbPlane blurred;       // the 1/8-size layer, after finish()
    bool finished = false;

    Impl(OIIO::ROI f, const BloomParams& p, int n)
        : frame(f), params(p), nthreads(n), nextRow(f.ybegin), metering(p.metering),
          quarter(f.width(), f.height(), std::max(1, f.width() / 4), std::max(1, f.height() / 4)) {}
};

BloomBuilder::BloomBuilder(OIIO::ROI frame, const BloomParams& params, int nthreads)
    : m_impl(std::make_unique<Impl>(frame, params, nthreads)) {}

BloomBuilder::~BloomBuilder() = default;

bool BloomBuilder::addRows(const OIIO::ImageBuf& strip) {
    Impl& m = *m_impl;
    if (!strip.initialized() || strip.nchannels() < 3 || strip.deep()) {
        m_error = "bloom needs a flat image with at least three channels";
        return false;
    }
    const OIIO::ROI r = strip.roi();
    if (r.xbegin != m.frame.xbegin || r.xend != m.frame.xend || r.ybegin != m.nextRow ||
        r.yend > m.frame.yend) {
        m_error = "bloom: strips must be whole rows of the frame, in order";
        return false;
    }
    // Metered on the full image with its alpha, exactly as dhdr-tonemap meters it: pixels
    // with alpha 0 (no surface) are left out, so an empty background does not lower the key
    // and make everything bloom.
    m.metering.add(strip, {}, m.nthreads);
    const detail::FloatPixels in(strip);
    for (int y = r.ybegin; y < r.yend; ++y) {
        m.quarter.addRow(y - m.frame.ybegin, in.at(r.xbegin, y), size_t(strip.nchannels()));
    }
    m.nextRow = r.yend;
    return true;
}

bool BloomBuilder::finish() {
    Impl& m = *m_impl;
    if (m.nextRow != m.frame.yend) {
        m_error = "bloom: the frame's rows have not all been added";
        return false;
    }
    const LuminanceStats stats = m.metering.result();
    const RgbPlane bright = brightPass(m.quarter.result(), stats.logAverage, m.params, m.nthreads);
    const RgbPlane eighth = detail::boxDownsample(bright, std::max(1, bright.width / 2),
                                                  std::max(1, bright.height / 2), m.nthreads);
    m.blurred = detail::gaussianBlur(eighth, m.params.sigma, m.nthreads);
    m.finished = true;
    return true;
}

void BloomBuilder::layerAt(int x, int y, float rgb[3]) const {
    const Impl& m = *m_impl;
    const float sx = float(m.blurred.width) / float(m.frame.width());
    const float sy = float(m.blurred.height) / float(m.frame.height());
    detail::bilinearSample(m.blurred, (float(x - m.frame.xbegin) + 0.5f) * sx,
                           (float(y - m.frame.ybegin) + 0.5f) * sy, rgb);
}

bool BloomBuilder::apply(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi) const {
    const Impl& m = *m_impl;
    if (!m.finished) {
        dst.errorfmt("bloom: finish() first");
        return false;
    }
    if (&dst != &src && !detail::prepareFloatDst(dst, src, roi, 3)) return false;
    if (!roi.defined()) roi = OIIO::roi_intersection(src.roi(), dst.roi());
    const detail::FloatPixels in(src);
    const float strength = m.params.strength;
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(m.nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                float b[3];
                layerAt(x, y, b);
                const float* p = in.at(x, y);
                float* q = detail::floatPixel(dst, x, y);
                for (int c = 0; c < 3; ++c)
                    q[c] = p[c] + strength * b[c];
            }
    });
    return true;
}

bool bloomLayer(OIIO::ImageBuf& layer, const OIIO::ImageBuf& src, const BloomParams& params,
                int nthreads) {
    BloomBuilder builder(src.roi(), params, nthreads);
    if (!builder.addRows(src) || !builder.finish()) {
        layer.errorfmt("{}", builder.error());
        return false;
    }
    const OIIO::ROI roi = src.roi();
    layer.reset(OIIO::ImageSpec(roi.width(), roi.height(), 3, OIIO::TypeDesc::FLOAT));
    layer.set_origin(roi.xbegin, roi.ybegin);
    OIIO::parallel_for(
        0, roi.height(),
        [&](int64_t y) {
            for (int x = 0; x < roi.width(); ++x)
                builder.layerAt(roi.xbegin + x, roi.ybegin + int(y),
                                detail::floatPixel(layer, roi.xbegin + x, roi.ybegin + int(y)));
        },
        perItem(nthreads));
    return true;
}

bool bloom(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const BloomParams& params, OIIO::ROI roi,
           int nthreads) {
    BloomBuilder builder(src.roi(), params, nthreads);
    if (!builder.addRows(src) || !builder.finish()) {
        dst.errorfmt("{}", builder.error());
        return false;
    }
    return builder.apply(dst, src, roi);
}

} // namespace dhdr
