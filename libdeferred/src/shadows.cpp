#include <algorithm>
#include <dhdr/deferred/light_sample.h>
#include <dhdr/deferred/sampling.h>
#include <dhdr/deferred/shadows.h>

namespace dhdr {

namespace {

ShadowRay towards(const SurfacePoint& at, const LightLiSample& s) {
    return {offsetRayOrigin(at, s.wi), s.wi, s.distance * (1.0f - kShadowRayShortening)};
}

} // namespace

float lightVisibility(const Light& light, const SurfacePoint& at, const glm::vec3& N,
                      std::uint64_t seed, int samples, const Visibility& visibility,
                      long long* rays) {
    if (light.type == LightType::Ambient) return 1.0f;
    if (!light.isArea() && light.type != LightType::Environment) {
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
            if (s.pdf == 0.0f || !(cosTheta > 0.0f)) continue;
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
