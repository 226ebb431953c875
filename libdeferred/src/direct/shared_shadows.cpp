// Many area lights at a point sharing one budget of shadow rays, chosen by each light's
// unshadowed contribution (shadows.h, sharedLightVisibility).
#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/direct/shadows.h>
#include <dhdr/deferred/lights/area.h>
#include <dhdr/deferred/lights/light.h>
#include <vector>

namespace dhdr {

namespace {

// One light's share of the rays: its ratio sums (Σ u V, Σ u) and how many were traced.
struct LightSums {
    double seen = 0.0, total = 0.0;           // Σ u V and Σ u
    double pooledSeen = 0.0, pooledAll = 0.0; // its share of the pooled sums
    int drawn = 0, traced = 0;                // rays that picked it, and of those traced
};

} // namespace

glm::vec3 sharedLightVisibility(const Light* const* lights, const glm::vec3* unshadowed,
                                size_t count, const SurfacePoint& at, const glm::vec3& N,
                                std::uint64_t seed, int samples, const Visibility& visibility,
                                long long* rays) {
    // Per thread, so that a pixel allocates nothing: the running sum of the lights' selection
    // probabilities, each light's sums, and E_i (computed when light i is first picked).
    thread_local std::vector<double> cdf;
    thread_local std::vector<LightSums> sums;
    thread_local std::vector<float> irradiance;
    cdf.resize(count);
    sums.assign(count, LightSums{});
    irradiance.assign(count, -1.0f);
    glm::dvec3 total(0.0);
    double luminanceSum = 0.0;
    for (size_t i = 0; i < count; ++i) {
        luminanceSum += std::max(double(luminance(unshadowed[i])), 0.0);
        total += glm::dvec3(unshadowed[i]);
    }
    if (!(luminanceSum > 0.0) || samples <= 0) return glm::vec3(total);
    // q_i = (1 − α) p_i + α / n with p_i ∝ luminance: while the n lights are no more than the
    // rays (α = n / samples), every q_i ≥ 1 / samples, and the stratified u.x (spaced exactly
    // 1 / samples apart) gives each light at least one ray; beyond, q_i = p_i (α = 0).
    const double n = double(count), alpha = n <= double(samples) ? n / double(samples) : 0.0;
    double running = 0.0;
    for (size_t i = 0; i < count; ++i) {
        running += (1.0 - alpha) * std::max(double(luminance(unshadowed[i])), 0.0) / luminanceSum +
                   alpha / n;
        cdf[i] = running;
    }

    constexpr int kBatch = 64;
    thread_local ShadowRay batch[kBatch];
    size_t picked[kBatch];
    double weight[kBatch];
    float transmittance[kBatch];
    const RotatedHammersley sequence(seed);
    // The pooled sums of every ray, Σ w V and Σ w with w = luminance(c_i) / q_i · u, for the
    // lights few rays pick. In double and in sample order: the same value for any thread count.
    double seen = 0.0, all = 0.0;
    int traced = 0, open = 0, closed = 0;
    for (int begin = 0; begin < samples; begin += kBatch) {
        int k = 0;
        for (int s = begin; s < std::min(samples, begin + kBatch); ++s) {
            const glm::vec2 u = sequence(std::uint32_t(s), std::uint32_t(samples));
            const double target = double(u.x) * running;
            const size_t i = std::min(
                size_t(std::upper_bound(cdf.begin(), cdf.end(), target) - cdf.begin()), count - 1);
            const double lo = i ? cdf[i - 1] : 0.0, share = cdf[i] - lo;
            if (!(share > 0.0)) continue;
            ++sums[i].drawn;
            const float ux = std::clamp(float((target - lo) / share), 0.0f, 0x1.fffffep-1f);
            const Light& light = *lights[i];
            const LightLiSample ls = sampleAreaLight(light, at.P, {ux, u.y});
            const float cosTheta = glm::dot(N, ls.wi);
            if (ls.pdf == 0.0f || !(cosTheta > 0.0f) || !leavesSurface(at, ls.wi)) continue;
            if (irradiance[i] < 0.0f) irradiance[i] = areaLightIrradiance(light, at.P, N);
            // The sample's share of its light's irradiance (mean 1 over the light), or 1 where
            // the light subtends no measurable cosine (a sliver at the horizon).
            weight[k] = irradiance[i] > 0.0f
                            ? double(cosTheta) / double(ls.pdf) / double(irradiance[i])
                            : 1.0;
            picked[k] = i;
            batch[k++] = {offsetRayOrigin(at, ls.wi), ls.wi,
                          ls.distance * (1.0f - kShadowRayShortening)};
        }
        visibility.test(batch, size_t(k), transmittance);
        if (rays) *rays += k;
        for (int j = 0; j < k; ++j) {
            const size_t i = picked[j];
            const double v = transmittance[j];
            sums[i].seen += weight[j] * v;
            sums[i].total += weight[j];
            ++sums[i].traced;
            const double w = std::max(double(luminance(unshadowed[i])), 0.0) * weight[j] /
                             (cdf[i] - (i ? cdf[i - 1] : 0.0));
            all += w;
            seen += w * v;
            sums[i].pooledAll += w;
            sums[i].pooledSeen += w * v;
            ++traced;
            open += transmittance[j] == 1.0f;
            closed += transmittance[j] == 0.0f;
        }
    }
    // Wholly lit or wholly hidden points are exact whatever the weights' rounding; with no
    // sample above the horizon the unshadowed value stands, as for one light.
    if (open == traced) return glm::vec3(total);
    if (closed == traced) return glm::vec3(0.0f);
    glm::dvec3 shadowed(0.0);
    for (size_t i = 0; i < count; ++i) {
        const LightSums& l = sums[i];
        const glm::dvec3 c(unshadowed[i]);
        const double picked =
            std::min(1.0, double(samples) * (cdf[i] - (i ? cdf[i - 1] : 0.0)) / running);
        if (picked >= 1.0) {
            // Its own ratio, as lightVisibility's: exactly 0 or 1 where its rays agree, and
            // the unshadowed value where none was above the horizon.
            shadowed += l.total > 0.0 ? c * (l.seen / l.total) : c;
            continue;
        }
        // A light picked with probability P_i = K q_i < 1 (K rays spaced 1 / K apart, with a
        // uniform offset): the pooled ratio V of the other lights' rays, corrected by what its
        // own rays saw, (m − V) / P_i with m the mean of u V over them (unbiased, as u's mean
        // is 1), when a ray picked it. Exact where every ray agrees; the pooled ratio leaves a
        // small bias (docs/lighting.md, "Many emitters").
        const double rest = all - l.pooledAll;
        const double pooled = rest > 0.0 ? (seen - l.pooledSeen) / rest : 1.0;
        const double mean = l.traced > 0 ? l.seen / double(l.traced) : 1.0;
        shadowed += c * (l.drawn > 0 ? pooled + (mean - pooled) / picked : pooled);
    }
    // The corrections may overshoot below 0 where a rarely picked light is hidden.
    shadowed = glm::max(shadowed, glm::dvec3(0.0));
    return glm::vec3(shadowed);
}

} // namespace dhdr
