#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/render/pixel_filter.h>

namespace dhdr {

double pixelFilterValue(PixelFilter filter, double width, double x) {
    const double half = 0.5 * width;
    if (!(std::abs(x) <= half)) return 0.0;
    switch (filter) {
    case PixelFilter::Box:
        return 1.0;
    case PixelFilter::Gaussian: {
        const double sigma = width / 6.0;
        return std::exp(-x * x / (2.0 * sigma * sigma)) -
               std::exp(-half * half / (2.0 * sigma * sigma));
    }
    case PixelFilter::BlackmanHarris: {
        const double t = 2.0 * M_PI * (x / width + 0.5);
        return 0.35875 - 0.48829 * std::cos(t) + 0.14128 * std::cos(2.0 * t) -
               0.01168 * std::cos(3.0 * t);
    }
    }
    return 0.0;
}

namespace {
constexpr int kSteps = 8192;   // integration intervals across the width
constexpr int kInverse = 1025; // inverse-CDF table entries
} // namespace

PixelFilterSampler::PixelFilterSampler(PixelFilter filter, float width) {
    // The cumulative distribution by the trapezoid rule in double, then inverted at evenly
    // spaced probabilities by linear interpolation between the integration points.
    const double w = double(width), step = w / kSteps;
    std::vector<double> cdf(kSteps + 1, 0.0);
    for (int i = 1; i <= kSteps; ++i) {
        const double a = -0.5 * w + step * (i - 1), b = a + step;
        cdf[size_t(i)] =
            cdf[size_t(i) - 1] +
            0.5 * step * (pixelFilterValue(filter, w, a) + pixelFilterValue(filter, w, b));
    }
    const double total = cdf.back();
    m_inverse.resize(kInverse);
    size_t i = 0;
    for (int j = 0; j < kInverse; ++j) {
        const double u = total * double(j) / double(kInverse - 1);
        while (i + 1 < size_t(kSteps) && cdf[i + 1] < u)
            ++i;
        const double span = cdf[i + 1] - cdf[i];
        const double f = span > 0.0 ? std::clamp((u - cdf[i]) / span, 0.0, 1.0) : 0.0;
        m_inverse[size_t(j)] = float(-0.5 * w + step * (double(i) + f));
    }
}

float PixelFilterSampler::offset(float u) const {
    const float s = std::clamp(u, 0.0f, 1.0f) * float(kInverse - 1);
    const int i = std::min(int(s), kInverse - 2);
    const float f = s - float(i);
    return m_inverse[size_t(i)] + f * (m_inverse[size_t(i) + 1] - m_inverse[size_t(i)]);
}

glm::vec2 PixelFilterSampler::rayOffset(int x, int y, int k, int n) const {
    const std::uint64_t h = sampleSeed(x, y, k, 0x5a4d91); // the pixel's rays, apart from light
    const float jx = unitFloat(h), jy = unitFloat(mixBits(h));
    const float u = (float(k % n) + jx) / float(n), v = (float(k / n) + jy) / float(n);
    return {offset(u), offset(v)};
}

} // namespace dhdr
