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

void atrousFilter(const std::vector<DenoiseEstimate>& estimates, const DenoiseGuide& guide,
                  int nthreads) {
    const int w = guide.width, h = guide.height;
    const size_t n = size_t(w) * size_t(h);
    if (n == 0) return;
    for (const DenoiseEstimate& e : estimates)
        if (!e.planes || (e.count != 1 && e.count != 2) || e.planes->size() < n * size_t(e.count) ||
            (e.direction && (!e.width || e.direction->size() < n || e.width->size() < n)))
            return;
    const size_t m = estimates.size();
    // Per estimate: its signal, and its variance per pixel from the 5 × 5 neighbourhood of the
    // same surface (SVGF's spatial estimate where no history is), then filtered along with it.
    std::vector<std::vector<float>> signal(m, std::vector<float>(n)),
        variance(m, std::vector<float>(n, 0.0f)), nextVariance(m, std::vector<float>(n));
    auto refreshSignals = [&] {
        for (size_t e = 0; e < m; ++e)
            for (size_t p = 0; p < n; ++p)
                signal[e][p] = signalAt(*estimates[e].planes, estimates[e].count, n, p);
    };
    refreshSignals();
    // Each tap's geometry weight is computed once and serves every estimate.
    OIIO::parallel_for(
        0, h,
        [&](int64_t yy) {
            const int y = int(yy);
            std::vector<double> s(m), s2(m);
            for (int x = 0; x < w; ++x) {
                const size_t p = size_t(y) * size_t(w) + size_t(x);
                if (!guide.surface[p]) continue;
                std::fill(s.begin(), s.end(), 0.0);
                std::fill(s2.begin(), s2.end(), 0.0);
                double weights = 0.0;
                for (int j = -2; j <= 2; ++j)
                    for (int i = -2; i <= 2; ++i) {
                        const int qx = x + i, qy = y + j;
                        if (qx < 0 || qx >= w || qy < 0 || qy >= h) continue;
                        const size_t q = size_t(qy) * size_t(w) + size_t(qx);
                        const double wq = geometryWeight(guide, p, q);
                        if (!(wq > 0.0)) continue;
                        for (size_t e = 0; e < m; ++e) {
                            s[e] += wq * signal[e][q];
                            s2[e] += wq * double(signal[e][q]) * signal[e][q];
                        }
                        weights += wq;
                    }
                for (size_t e = 0; e < m; ++e) {
                    const double mean = s[e] / weights;
                    variance[e][p] = float(std::max(0.0, s2[e] / weights - mean * mean));
                }
            }
        },
        perItem(nthreads));
    std::vector<std::vector<float>> next(m);
    for (size_t e = 0; e < m; ++e)
        next[e].resize(estimates[e].planes->size());
    for (int pass = 0; pass < kDenoiseIterations; ++pass) {
        const int step = 1 << pass;
        OIIO::parallel_for(
            0, h,
            [&](int64_t yy) {
                const int y = int(yy);
                std::vector<double> sum(2 * m), weights(m), var(m);
                std::vector<float> spread(m);
                for (int x = 0; x < w; ++x) {
                    const size_t p = size_t(y) * size_t(w) + size_t(x);
                    if (!guide.surface[p]) {
                        for (size_t e = 0; e < m; ++e) {
                            for (int c = 0; c < estimates[e].count; ++c)
                                next[e][size_t(c) * n + p] =
                                    (*estimates[e].planes)[size_t(c) * n + p];
                            nextVariance[e][p] = variance[e][p];
                        }
                        continue;
                    }
                    for (size_t e = 0; e < m; ++e)
                        spread[e] = kSignalSigma * std::sqrt(variance[e][p]) + 1e-4f;
                    std::fill(sum.begin(), sum.end(), 0.0);
                    std::fill(weights.begin(), weights.end(), 0.0);
                    std::fill(var.begin(), var.end(), 0.0);
                    // Taps in a fixed order: the same sums whatever the threads.
                    for (int j = -2; j <= 2; ++j) {
                        const int qy = y + j * step;
                        if (qy < 0 || qy >= h) continue;
                        for (int i = -2; i <= 2; ++i) {
                            const int qx = x + i * step;
                            if (qx < 0 || qx >= w) continue;
                            const size_t q = size_t(qy) * size_t(w) + size_t(qx);
                            const float geometry = geometryWeight(guide, p, q);
                            if (!(geometry > 0.0f)) continue;
                            const float kernel = kKernel[i + 2] * kKernel[j + 2];
                            for (size_t e = 0; e < m; ++e) {
                                // exp(0) = 1 spared where the estimates agree (open sky).
                                const float difference = std::abs(signal[e][q] - signal[e][p]);
                                float weight =
                                    geometry * kernel *
                                    (difference > 0.0f ? std::exp(-difference / spread[e]) : 1.0f);
                                if (estimates[e].direction && q != p) {
                                    const float width = (*estimates[e].width)[p];
                                    const float turn =
                                        1.0f - glm::dot((*estimates[e].direction)[p],
                                                        (*estimates[e].direction)[q]);
                                    weight *= std::exp(-std::max(turn, 0.0f) / (width * width));
                                }
                                weights[e] += weight;
                                var[e] += double(weight) * weight * variance[e][q];
                                const std::vector<float>& planes = *estimates[e].planes;
                                for (int c = 0; c < estimates[e].count; ++c)
                                    sum[2 * e + size_t(c)] +=
                                        double(weight) * planes[size_t(c) * n + q];
                            }
                        }
                    }
                    for (size_t e = 0; e < m; ++e) {
                        for (int c = 0; c < estimates[e].count; ++c)
                            next[e][size_t(c) * n + p] = float(sum[2 * e + size_t(c)] / weights[e]);
                        nextVariance[e][p] = float(var[e] / (weights[e] * weights[e]));
                    }
                }
            },
            perItem(nthreads));
        for (size_t e = 0; e < m; ++e) {
            estimates[e].planes->swap(next[e]);
            variance[e].swap(nextVariance[e]);
        }
        refreshSignals();
    }
}

void atrousFilter(std::vector<float>& planes, int count, const DenoiseGuide& guide, int nthreads) {
    atrousFilter({DenoiseEstimate{&planes, count}}, guide, nthreads);
}

} // namespace dhdr
