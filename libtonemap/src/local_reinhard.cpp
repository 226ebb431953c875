#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/tonemap/local_reinhard.h>
#include <memory>
#include <utility>
#include <vector>

namespace dhdr {

namespace {

// A width × height float raster, left uninitialized: each is written whole before it is read,
// and zero-filling the 4K rasters cost more than blurring them.
struct Raster {
    Raster(int width, int height) : width(width), height(height) {
        data.reset(new float[size_t(width) * size_t(height)]);
    }
    float* row(int y) { return data.get() + size_t(y) * size_t(width); }
    const float* row(int y) const { return data.get() + size_t(y) * size_t(width); }
    float& operator[](size_t k) { return data[k]; }
    float operator[](size_t k) const { return data[k]; }
    size_t size() const { return size_t(width) * size_t(height); }

    int width, height;
    std::unique_ptr<float[]> data;
};

// dst = src convolved with the separable Gaussian of standard deviation σ (normalized,
// radius ⌈3σ⌉, edges clamped); `tmp` holds the pass along x.
void gaussian(Raster& dst, const Raster& src, Raster& tmp, double sigma, int nthreads) {
    const int radius = std::max(1, int(std::ceil(3.0 * sigma)));
    std::vector<double> kernel(static_cast<size_t>(2 * radius + 1));
    double total = 0.0;
    for (int i = -radius; i <= radius; ++i) {
        kernel[size_t(i + radius)] = std::exp(-0.5 * i * i / (sigma * sigma));
        total += kernel[size_t(i + radius)];
    }
    for (double& k : kernel)
        k /= total;
    // Each pass sums whole rows, Σ_k g_k · row(k), so that the inner loop runs along memory.
    const int width = src.width, height = src.height;
    const size_t w = size_t(width);
    // Along x: the row padded with its edge values on both sides.
    OIIO::parallel_for(
        0, height,
        [&](int64_t y) {
            const float* row = src.row(int(y));
            std::vector<float> padded(w + 2 * size_t(radius));
            for (size_t i = 0; i < padded.size(); ++i)
                padded[i] = row[std::clamp(int(i) - radius, 0, width - 1)];
            std::vector<double> sum(w, 0.0);
            for (size_t k = 0; k < kernel.size(); ++k) {
                const double g = kernel[k];
                const float* p = &padded[k];
                for (size_t x = 0; x < w; ++x)
                    sum[x] += g * p[x];
            }
            std::copy(sum.begin(), sum.end(), tmp.row(int(y)));
        },
        perItem(nthreads));
    // Along y: rows above and below, clamped to the image.
    OIIO::parallel_for(
        0, height,
        [&](int64_t y) {
            std::vector<double> sum(w, 0.0);
            for (int k = -radius; k <= radius; ++k) {
                const double g = kernel[size_t(k + radius)];
                const float* p = tmp.row(std::clamp(int(y) + k, 0, height - 1));
                for (size_t x = 0; x < w; ++x)
                    sum[x] += g * p[x];
            }
            std::copy(sum.begin(), sum.end(), dst.row(int(y)));
        },
        perItem(nthreads));
}

} // namespace

bool localReinhard(OIIO::ImageBuf& dst, const OIIO::ImageBuf& scaledLuminance,
                   const LocalReinhardParams& params, int nthreads) {
    const OIIO::ROI roi = scaledLuminance.roi();
    const int width = roi.width(), height = roi.height();
    Raster L(width, height), v1(width, height), v2(width, height), chosen(width, height),
        tmp(width, height);
    scaledLuminance.get_pixels(OIIO::ROI(roi.xbegin, roi.xend, roi.ybegin, roi.yend, 0, 1, 0, 1),
                               OIIO::TypeDesc::FLOAT, L.data.get());

    // Gaussian of scale s: R(x, y, s) ∝ exp(−(x² + y²) / (α₁ s)²), so σ = α₁ s / √2 = s / 4.
    const double alpha1 = 1.0 / (2.0 * std::sqrt(2.0));
    auto blurAt = [&](Raster& out, int i) {
        gaussian(out, L, tmp, alpha1 * std::pow(1.6, i) / std::sqrt(2.0), nthreads);
    };
    blurAt(v1, 0);
    std::copy(v1.data.get(), v1.data.get() + v1.size(), chosen.data.get()); // V1 at s_m so far
    std::vector<char> settled(L.size(), 0);
    for (int i = 0; i < params.scales; ++i) {
        const double s = std::pow(1.6, i);
        blurAt(v2, i + 1);
        const double sharpening = std::pow(2.0, params.phi) * params.key / (s * s);
        OIIO::parallel_for(
            0, height,
            [&](int64_t y) {
                for (size_t k = size_t(y) * size_t(width); k < size_t(y + 1) * size_t(width); ++k) {
                    if (settled[k]) continue;
                    const double activity = (double(v1[k]) - v2[k]) / (sharpening + v1[k]);
                    if (std::abs(activity) < params.epsilon)
                        chosen[k] = v1[k];
                    else
                        settled[k] = 1;
                }
            },
            perItem(nthreads));
        std::swap(v1.data, v2.data); // V1(1.6 s) is the next scale's V1
    }

    OIIO::ImageSpec spec(width, height, 1, OIIO::TypeDesc::FLOAT);
    spec.x = roi.xbegin;
    spec.y = roi.ybegin;
    dst.reset(spec, OIIO::InitializePixels::No);
    float* out = static_cast<float*>(dst.localpixels());
    for (size_t k = 0; k < L.size(); ++k)
        out[k] = L[k] / (1.0f + chosen[k]);
    return true;
}

} // namespace dhdr
