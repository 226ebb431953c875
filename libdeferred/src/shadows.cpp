#include <algorithm>
#include <cmath>
#include <dhdr/deferred/ibl.h>
#include <dhdr/deferred/lights/light.h>
#include <dhdr/deferred/sampling.h>
#include <dhdr/deferred/shadows.h>

namespace dhdr {

namespace {

ShadowRay towards(const SurfacePoint& at, const LightLiSample& s) {
    return {offsetRayOrigin(at, s.wi), s.wi, s.distance * (1.0f - kShadowRayShortening)};
}

} // namespace

// The visible share of an environment's diffuse light, by the ratio estimator of Heitz, Hill
// & McGuire (2018): Σ w V / Σ w over the same samples, w = Y(L) cos θ weighted by MIS.
// Half the samples are drawn by the environment's luminance, half cosine-weighted about N, and
// combined with the power heuristic (Veach 1997, eq. 9.13; pbrt-v4 PowerHeuristic): luminance
// sampling alone leaves a surface facing away from a bright sky with almost no sample above
// its horizon, and its visibility to the one or two that are (black speckles).
VisibilitySums environmentVisibilitySums(const Light& light, const SurfacePoint& at,
                                         const glm::vec3& N, std::uint64_t seed, int samples,
                                         const Visibility& visibility, long long* rays) {
    VisibilitySums sums;
    if (!light.ibl || light.ibl->sampler.empty()) return sums;
    const EnvironmentSampler& sampler = light.ibl->sampler;
    const int nLight = (samples + 1) / 2, nCosine = samples / 2;
    const RotatedHammersley lightSequence(seed), cosineSequence(seed ^ 0x2545f4914f6cdd1dull);
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    const glm::vec3 k = light.color * light.intensity;
    auto luminance = [](const glm::vec3& c) {
        return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
    };
    // Power heuristic of technique a against b, with n samples each and densities p.
    auto power = [](float na, float pa, float nb, float pb) {
        const float a = na * pa, bb = nb * pb;
        return a * a / (a * a + bb * bb);
    };
    constexpr int kBatch = 64;
    thread_local ShadowRay batch[kBatch];
    float weight[kBatch], transmittance[kBatch];
    double total = 0.0, seen = 0.0;
    int count = 0, open = 0, closed = 0;
    for (int begin = 0; begin < samples; begin += kBatch) {
        int n = 0;
        for (int i = begin; i < std::min(samples, begin + kBatch); ++i) {
            glm::vec3 wi, radiance;
            float w = 0.0f;
            if (i < nLight) {
                float pdf = 0.0f;
                const glm::vec3 d = sampler.sample(
                    lightSequence(std::uint32_t(i), std::uint32_t(nLight)), pdf, radiance);
                wi = fromEnvironment(light, d);
                const float cosTheta = glm::dot(N, wi);
                if (!(pdf > 0.0f) || !(cosTheta > 0.0f) || !(glm::dot(at.Ng, wi) > 0.0f)) continue;
                const float pCosine = cosTheta / kPi;
                w = luminance(radiance * k) * cosTheta / pdf *
                    power(float(nLight), pdf, float(nCosine), pCosine) / float(nLight);
            } else {
                const int j = i - nLight;
                const glm::vec3 h =
                    cosineHemisphere(cosineSequence(std::uint32_t(j), std::uint32_t(nCosine)));
                wi = glm::normalize(h.x * t + h.y * b + h.z * N);
                const float cosTheta = glm::dot(N, wi);
                if (!(cosTheta > 0.0f) || !(glm::dot(at.Ng, wi) > 0.0f)) continue;
                const float pCosine = cosTheta / kPi;
                const float pLight = sampler.lookup(intoEnvironment(light, wi), radiance);
                w = luminance(radiance * k) * cosTheta / pCosine *
                    power(float(nCosine), pCosine, float(nLight), pLight) / float(nCosine);
            }
            // Black sky weighs nothing either way: not traced.
            if (!(w > 0.0f)) continue;
            weight[n] = w;
            batch[n++] = {offsetRayOrigin(at, wi), wi, INFINITY};
        }
        visibility.test(batch, size_t(n), transmittance);
        if (rays) *rays += n;
        for (int i = 0; i < n; ++i) {
            total += weight[i];
            seen += weight[i] * double(transmittance[i]);
            ++count;
            open += transmittance[i] == 1.0f;
            closed += transmittance[i] == 0.0f;
        }
    }
    sums.seen = seen;
    sums.total = total;
    sums.count = count;
    sums.open = open;
    sums.closed = closed;
    return sums;
}

namespace {

float environmentVisibility(const Light& light, const SurfacePoint& at, const glm::vec3& N,
                            std::uint64_t seed, int samples, const Visibility& visibility,
                            long long* rays) {
    const VisibilitySums s =
        environmentVisibilitySums(light, at, N, seed, samples, visibility, rays);
    // As for area lights: no sample above the horizon leaves the unshadowed value; wholly
    // lit or hidden points are exact.
    if (s.open == s.count || !(s.total > 0.0)) return 1.0f;
    if (s.closed == s.count) return 0.0f;
    return float(s.seen / s.total);
}

} // namespace

float lightVisibility(const Light& light, const SurfacePoint& at, const glm::vec3& N,
                      std::uint64_t seed, int samples, const Visibility& visibility,
                      long long* rays) {
    if (light.type == LightType::Ambient) return 1.0f;
    if (light.type == LightType::Environment) {
        if (!light.ibl || light.ibl->sampler.empty()) return 1.0f;
        return environmentVisibility(light, at, N, seed, samples, visibility, rays);
    }
    const bool disk = light.type == LightType::Directional && light.angle > 0.0f;
    if (!light.isArea() && !disk) {
        const LightLiSample s = sampleLi(light, at.P, {0.0f, 0.0f});
        if (s.pdf == 0.0f) return 1.0f;
        if (rays) ++*rays;
        return visibility.transmittance(towards(at, s));
    }
    constexpr int kBatch = 64;
    // Per thread, so that the rays are not value-initialized again at every pixel.
    thread_local ShadowRay batch[kBatch];
    const RotatedHammersley sequence(seed);
    float weight[kBatch];
    float transmittance[kBatch];
    // Sums in double, in sample order: the same value for any thread count. Samples below
    // the horizon weigh nothing and are not traced.
    double total = 0.0, seen = 0.0, unweighted = 0.0;
    int count = 0, open = 0, closed = 0;
    for (int begin = 0; begin < samples; begin += kBatch) {
        int n = 0;
        for (int i = begin; i < std::min(samples, begin + kBatch); ++i) {
            const LightLiSample s =
                sampleLi(light, at.P, sequence(std::uint32_t(i), std::uint32_t(samples)));
            const float cosTheta = glm::dot(N, s.wi);
            if (s.pdf == 0.0f || !(cosTheta > 0.0f) || !(glm::dot(at.Ng, s.wi) > 0.0f)) continue;
            weight[n] = (s.L.r + s.L.g + s.L.b) * cosTheta / s.pdf;
            batch[n++] = towards(at, s);
        }
        visibility.test(batch, size_t(n), transmittance);
        if (rays) *rays += n;
        for (int i = 0; i < n; ++i) {
            total += weight[i];
            seen += weight[i] * double(transmittance[i]);
            unweighted += double(transmittance[i]);
            ++count;
            open += transmittance[i] == 1.0f;
            closed += transmittance[i] == 0.0f;
        }
    }
    // No sample above the horizon (a light grazing the surface): its unshadowed value stands.
    // Wholly lit or wholly hidden points are exact whatever the weights' rounding.
    if (open == count) return 1.0f;
    if (closed == count) return 0.0f;
    return float(total > 0.0 ? seen / total : unweighted / count);
}

} // namespace dhdr
