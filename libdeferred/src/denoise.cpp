#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/denoise.h>

namespace dhdr {

namespace {

constexpr float kKernel[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};
// SVGF's σ_l: how many standard deviations of the estimate a difference may be and still mix.
constexpr float kSignalSigma = 4.0f;

// The quantity whose edges the filter keeps: the ratio of a pair of planes (shadowed over
// unshadowed light; 1 where nothing was seen) or the one plane's value.
float signalAt(const std::vector<float>& planes, int count, size_t n, size_t p) {
    if (count == 2) {
        const float total = planes[n + p];
        return total > 0.0f ? planes[p] / total : 1.0f;
    }
    return planes[p];
}

// The guide's weight of tap q for pixel p: normals, tangent plane, object.
float geometryWeight(const DenoiseGuide& g, size_t p, size_t q) {
    if (!g.surface[q] || g.object[q] != g.object[p]) return 0.0f;
    if (q == p) return 1.0f;
    const float facing = std::max(0.0f, glm::dot(g.normal[p], g.normal[q]));
    float f = facing * facing; // facing^64 by squaring
    for (int k = 0; k < 5; ++k)
        f *= f;
    const glm::vec3 d = g.position[q] - g.position[p];
    const float distance = glm::length(d);
    const float off =
        distance > 0.0f ? std::abs(glm::dot(g.normal[p], d)) / (0.05f * distance) : 0.0f;
    return f * std::exp(-off * off);
}

} // namespace

void atrousFilter(std::vector<float>& planes, int count, const DenoiseGuide& guide, int nthreads) {
    const int w = guide.width, h = guide.height;
    const size_t n = size_t(w) * size_t(h);
    if ((count != 1 && count != 2) || n == 0 || planes.size() < n * size_t(count)) return;
    // The estimate's variance per pixel, from the 5 × 5 neighbourhood of the same surface
    // (SVGF's spatial estimate where no history is), then filtered along with it.
    std::vector<float> signal(n), variance(n, 0.0f), nextVariance(n);
    for (size_t p = 0; p < n; ++p)
        signal[p] = signalAt(planes, count, n, p);
    OIIO::parallel_for(
        0, h,
        [&](int64_t yy) {
            const int y = int(yy);
            for (int x = 0; x < w; ++x) {
                const size_t p = size_t(y) * size_t(w) + size_t(x);
                if (!guide.surface[p]) continue;
                double s = 0.0, s2 = 0.0, weights = 0.0;
                for (int j = -2; j <= 2; ++j)
                    for (int i = -2; i <= 2; ++i) {
                        const int qx = x + i, qy = y + j;
                        if (qx < 0 || qx >= w || qy < 0 || qy >= h) continue;
                        const size_t q = size_t(qy) * size_t(w) + size_t(qx);
                        const double wq = geometryWeight(guide, p, q);
                        if (!(wq > 0.0)) continue;
                        s += wq * signal[q];
                        s2 += wq * double(signal[q]) * signal[q];
                        weights += wq;
                    }
                const double mean = s / weights;
                variance[p] = float(std::max(0.0, s2 / weights - mean * mean));
            }
        },
        perItem(nthreads));
    std::vector<float> next(planes.size());
    for (int pass = 0; pass < kDenoiseIterations; ++pass) {
        const int step = 1 << pass;
        OIIO::parallel_for(
            0, h,
            [&](int64_t yy) {
                const int y = int(yy);
                for (int x = 0; x < w; ++x) {
                    const size_t p = size_t(y) * size_t(w) + size_t(x);
                    if (!guide.surface[p]) {
                        for (int c = 0; c < count; ++c)
                            next[size_t(c) * n + p] = planes[size_t(c) * n + p];
                        nextVariance[p] = variance[p];
                        continue;
                    }
                    const float spread = kSignalSigma * std::sqrt(variance[p]) + 1e-4f;
                    double sum[2] = {0.0, 0.0}, weights = 0.0, var = 0.0;
                    // Taps in a fixed order: the same sums whatever the threads.
                    for (int j = -2; j <= 2; ++j) {
                        const int qy = y + j * step;
                        if (qy < 0 || qy >= h) continue;
                        for (int i = -2; i <= 2; ++i) {
                            const int qx = x + i * step;
                            if (qx < 0 || qx >= w) continue;
                            const size_t q = size_t(qy) * size_t(w) + size_t(qx);
                            float weight = geometryWeight(guide, p, q);
                            if (!(weight > 0.0f)) continue;
                            weight *= kKernel[i + 2] * kKernel[j + 2] *
                                      std::exp(-std::abs(signal[q] - signal[p]) / spread);
                            weights += weight;
                            var += double(weight) * weight * variance[q];
                            for (int c = 0; c < count; ++c)
                                sum[c] += double(weight) * planes[size_t(c) * n + q];
                        }
                    }
                    for (int c = 0; c < count; ++c)
                        next[size_t(c) * n + p] = float(sum[c] / weights);
                    nextVariance[p] = float(var / (weights * weights));
                }
            },
            perItem(nthreads));
        planes.swap(next);
        variance.swap(nextVariance);
        for (size_t p = 0; p < n; ++p)
            signal[p] = signalAt(planes, count, n, p);
    }
}

} // namespace dhdr
