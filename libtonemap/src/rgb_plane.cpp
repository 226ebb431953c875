#include "rgb_plane.h"

#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>

namespace dhdr::detail {

namespace {

// Weights of input pixels [first, first + weights.size()) for one output pixel of a 1-D box.
struct Footprint {
    int first = 0;
    std::vector<float> weights;
};

std::vector<Footprint> boxFootprints(int srcSize, int dstSize) {
    std::vector<Footprint> out(static_cast<size_t>(dstSize));
    const double ratio = double(srcSize) / double(dstSize);
    for (int i = 0; i < dstSize; ++i) {
        const double a = i * ratio, b = (i + 1) * ratio;
        Footprint& f = out[size_t(i)];
        f.first = int(std::floor(a));
        const int last = std::min(srcSize - 1, int(std::ceil(b)) - 1);
        for (int s = f.first; s <= last; ++s) {
            const double cover = std::min(b, double(s + 1)) - std::max(a, double(s));
            f.weights.push_back(float(cover / ratio));
        }
    }
    return out;
}

// One separable pass along x (horizontal) or y, with per-output-pixel footprints.
RgbPlane convolve(const RgbPlane& src, int width, int height, bool horizontal,
                  const std::vector<Footprint>& footprints, int nthreads) {
    RgbPlane dst(width, height);
    const int srcLen = horizontal ? src.width : src.height;
    OIIO::parallel_for(
        0, height,
        [&](int64_t y) {
            for (int x = 0; x < width; ++x) {
                const Footprint& f = footprints[size_t(horizontal ? x : y)];
                double sum[3] = {0.0, 0.0, 0.0};
                for (size_t k = 0; k < f.weights.size(); ++k) {
                    const int s = std::clamp(f.first + int(k), 0, srcLen - 1);
                    const float* p = horizontal ? src.at(s, int(y)) : src.at(x, s);
                    for (int c = 0; c < 3; ++c)
                        sum[c] += double(f.weights[k]) * p[c];
                }
                float* q = dst.at(x, int(y));
                for (int c = 0; c < 3; ++c)
                    q[c] = float(sum[c]);
            }
        },
        dhdr::perItem(nthreads));
    return dst;
}

} // namespace

RgbPlane boxDownsample(const RgbPlane& src, int width, int height, int nthreads) {
    const RgbPlane wide =
        convolve(src, width, src.height, true, boxFootprints(src.width, width), nthreads);
    return convolve(wide, width, height, false, boxFootprints(src.height, height), nthreads);
}

struct BoxDownsampler::Impl {
    std::vector<Footprint> across, down; // horizontal and vertical footprints
    int srcWidth = 0, srcHeight = 0;
    int nextOutput = 0;                   // the next output row to compute
    int freedBelow = 0;                   // wide rows before this one are freed
    std::vector<std::vector<float>> wide; // horizontally reduced input rows, by row; freed
                                          // once no output row needs them
};

BoxDownsampler::BoxDownsampler(int srcWidth, int srcHeight, int width, int height)
    : m_impl(std::make_unique<Impl>()), m_out(width, height) {
    m_impl->across = boxFootprints(srcWidth, width);
    m_impl->down = boxFootprints(srcHeight, height);
    m_impl->srcWidth = srcWidth;
    m_impl->srcHeight = srcHeight;
    m_impl->wide.resize(size_t(srcHeight));
}

BoxDownsampler::~BoxDownsampler() = default;

void BoxDownsampler::addRow(int y, const float* rgb, size_t pixelStride) {
    Impl& m = *m_impl;
    // The horizontal pass of convolve() for this row: the same sums in the same order.
    std::vector<float>& row = m.wide[size_t(y)];
    row.assign(size_t(m_out.width) * 3, 0.0f);
    for (int x = 0; x < m_out.width; ++x) {
        const Footprint& f = m.across[size_t(x)];
        double sum[3] = {0.0, 0.0, 0.0};
        for (size_t k = 0; k < f.weights.size(); ++k) {
            const int s = std::clamp(f.first + int(k), 0, m.srcWidth - 1);
            const float* p = rgb + size_t(s) * pixelStride;
            for (int c = 0; c < 3; ++c)
                sum[c] += double(f.weights[k]) * p[c];
        }
        for (int c = 0; c < 3; ++c)
            row[size_t(x) * 3 + size_t(c)] = float(sum[c]);
    }
    // Every output row whose footprint ends at or before this row: the vertical pass.
    while (m.nextOutput < m_out.height) {
        const Footprint& f = m.down[size_t(m.nextOutput)];
        const int last = std::clamp(f.first + int(f.weights.size()) - 1, 0, m.srcHeight - 1);
        if (last > y) break;
        for (int x = 0; x < m_out.width; ++x) {
            double sum[3] = {0.0, 0.0, 0.0};
            for (size_t k = 0; k < f.weights.size(); ++k) {
                const int s = std::clamp(f.first + int(k), 0, m.srcHeight - 1);
                const float* p = &m.wide[size_t(s)][size_t(x) * 3];
                for (int c = 0; c < 3; ++c)
                    sum[c] += double(f.weights[k]) * p[c];
            }
            float* q = m_out.at(x, m.nextOutput);
            for (int c = 0; c < 3; ++c)
                q[c] = float(sum[c]);
        }
        ++m.nextOutput;
        // Rows before the next footprint are not needed again.
        const int keepFrom = m.nextOutput < m_out.height
                                 ? std::max(0, m.down[size_t(m.nextOutput)].first)
                                 : m.srcHeight;
        for (; m.freedBelow < std::min(keepFrom, m.srcHeight); ++m.freedBelow)
            std::vector<float>().swap(m.wide[size_t(m.freedBelow)]);
    }
}

RgbPlane gaussianBlur(const RgbPlane& src, float sigma, int nthreads) {
    if (!(sigma > 0.0f)) return src;
    const int radius = int(std::ceil(3.0f * sigma));
    std::vector<float> kernel(static_cast<size_t>(2 * radius + 1));
    double total = 0.0;
    for (int i = -radius; i <= radius; ++i) {
        const double g = std::exp(-0.5 * double(i * i) / double(sigma * sigma));
        kernel[size_t(i + radius)] = float(g);
        total += g;
    }
    // Normalized so that a flat image stays flat (the seed's weights sum to more than 1).
    for (float& k : kernel)
        k = float(k / total);

    auto footprints = [&](int size) {
        std::vector<Footprint> out(static_cast<size_t>(size));
        for (int i = 0; i < size; ++i)
            out[size_t(i)] = {i - radius, kernel};
        return out;
    };
    const RgbPlane wide =
        convolve(src, src.width, src.height, true, footprints(src.width), nthreads);
    return convolve(wide, src.width, src.height, false, footprints(src.height), nthreads);
}

void bilinearSample(const RgbPlane& src, float fx, float fy, float out[3]) {
    const float x = fx - 0.5f, y = fy - 0.5f;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const float tx = x - float(x0), ty = y - float(y0);
    auto px = [&](int xi, int yi) {
        return src.at(std::clamp(xi, 0, src.width - 1), std::clamp(yi, 0, src.height - 1));
    };
    const float *a = px(x0, y0), *b = px(x0 + 1, y0), *c = px(x0, y0 + 1), *d = px(x0 + 1, y0 + 1);
    for (int k = 0; k < 3; ++k)
        out[k] = (1 - ty) * ((1 - tx) * a[k] + tx * b[k]) + ty * ((1 - tx) * c[k] + tx * d[k]);
}

} // namespace dhdr::detail
