#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/tonemap/local_reinhard.h>
#include <vector>

namespace dhdr {

namespace {

// Separable Gaussian of standard deviation σ (normalized, radius ⌈3σ⌉, edges clamped) of a
// width × height float raster.
std::vector<float> gaussian(const std::vector<float>& src, int width, int height, double sigma,
                            int nthreads) {
    const int radius = std::max(1, int(std::ceil(3.0 * sigma)));
    std::vector<double> kernel(static_cast<size_t>(2 * radius + 1));
    double total = 0.0;
    for (int i = -radius; i <= radius; ++i) {
        kernel[size_t(i + radius)] = std::exp(-0.5 * i * i / (sigma * sigma));
        total += kernel[size_t(i + radius)];
    }
    for (double& k : kernel)
        k /= total;
    // One 1-D pass along x or y, edges clamped.
    auto pass = [&](const std::vector<float>& in, std::vector<float>& out, bool alongX) {
        OIIO::parallel_for(
            0, height,
            [&](int64_t y) {
                for (int x = 0; x < width; ++x) {
                    double sum = 0.0;
                    for (int k = -radius; k <= radius; ++k) {
                        const int xx = alongX ? std::clamp(x + k, 0, width - 1) : x;
                        const int yy = alongX ? int(y) : std::clamp(int(y) + k, 0, height - 1);
                        sum += kernel[size_t(k + radius)] *
                               in[size_t(yy) * size_t(width) + size_t(xx)];
                    }
                    out[size_t(y) * size_t(width) + size_t(x)] = float(sum);
                }
            },
            perItem(nthreads));
    };
    std::vector<float> tmp(src.size()), out(src.size());
    pass(src, tmp, true);
    pass(tmp, out, false);
    return out;
}

} // namespace

bool localReinhard(OIIO::ImageBuf& dst, const OIIO::ImageBuf& scaledLuminance,
                   const LocalReinhardParams& params, int nthreads) {
    const OIIO::ROI roi = scaledLuminance.roi();
    const int width = roi.width(), height = roi.height();
    std::vector<float> L(size_t(width) * size_t(height));
    scaledLuminance.get_pixels(OIIO::ROI(roi.xbegin, roi.xend, roi.ybegin, roi.yend, 0, 1, 0, 1),
                               OIIO::TypeDesc::FLOAT, L.data());

    // Gaussian of scale s: R(x, y, s) ∝ exp(−(x² + y²) / (α₁ s)²), so σ = α₁ s / √2 = s / 4.
    const double alpha1 = 1.0 / (2.0 * std::sqrt(2.0));
    auto blurAt = [&](int i) {
        return gaussian(L, width, height, alpha1 * std::pow(1.6, i) / std::sqrt(2.0), nthreads);
    };
    std::vector<float> chosen = blurAt(0); // V1 at the scale chosen so far
    std::vector<char> settled(L.size(), 0);
    std::vector<float> v1 = chosen;
    for (int i = 0; i < params.scales; ++i) {
        const double s = std::pow(1.6, i);
        const std::vector<float> v2 = blurAt(i + 1);
        const double sharpening = std::pow(2.0, params.phi) * params.key / (s * s);
        OIIO::parallel_for(
            int64_t(0), int64_t(L.size()),
            [&](int64_t k) {
                if (settled[size_t(k)]) return;
                const double activity =
                    (double(v1[size_t(k)]) - v2[size_t(k)]) / (sharpening + v1[size_t(k)]);
                if (std::abs(activity) < params.epsilon)
                    chosen[size_t(k)] = v1[size_t(k)];
                else
                    settled[size_t(k)] = 1;
            },
            perItem(nthreads));
        v1 = v2;
    }

    OIIO::ImageSpec spec(width, height, 1, OIIO::TypeDesc::FLOAT);
    spec.x = roi.xbegin;
    spec.y = roi.ybegin;
    dst.reset(spec);
    float* out = static_cast<float*>(dst.localpixels());
    for (size_t k = 0; k < L.size(); ++k)
        out[k] = L[k] / (1.0f + chosen[k]);
    return true;
}

} // namespace dhdr
