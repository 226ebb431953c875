#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/direct/shadows.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/lights/light.h>

namespace dhdr {

namespace {

ShadowRay towards(const SurfacePoint& at, const LightLiSample& s) {
    return {offsetRayOrigin(at, s.wi), s.wi, s.distance * (1.0f - kShadowRayShortening)};
}

// A sun's disk is wholly seen or wholly hidden from most points. A first set of its rays
// decides a point when every one is open or every one is blocked; elsewhere all the samples
// are traced, which gives the value without this step. The first set is a quarter of the
// samples, each the first of the set in the outer half of the disk's area (u.x ≥ ½) within
// one sector of angle, since an occluder's edge that cuts into the disk crosses its rim
// first. It misses an occluder that hides only a sliver of the disk between two of them, so
// it runs only up to 64 samples (the default is 16); more samples trace every ray.
// Returns −1 where it does not decide (docs/lights.md, `angle`).
float sunDiskProbe(const Light& light, const SurfacePoint& at, const glm::vec3& N,
                   const RotatedHammersley& sequence, int samples, const Visibility& visibility,
                   long long* rays) {
    if (samples < 8 || samples > 64) return -1.0f;
    const int cells = samples / 4;
    int pick[16];
    std::fill(pick, pick + cells, -1);
    int found = 0;
    for (int i = 0; i < samples && found < cells; ++i) {
        const glm::vec2 u = sequence(std::uint32_t(i), std::uint32_t(samples));
        if (u.x < 0.5f) continue;
        const int cell = std::min(int(u.y * float(cells)), cells - 1);
        if (pick[cell] < 0) {
            pick[cell] = i;
            ++found;
        }
    }
    if (found < cells) return -1.0f;
    ShadowRay batch[16];
    float transmittance[16];
    for (int c = 0; c < cells; ++c) {
        const LightLiSample s =
            sampleLi(light, at.P, sequence(std::uint32_t(pick[c]), std::uint32_t(samples)));
        if (s.pdf == 0.0f || !(glm::dot(N, s.wi) > 0.0f) || !(glm::dot(at.Ng, s.wi) > 0.0f))
            return -1.0f;
        batch[c] = towards(at, s);
    }
    visibility.testCoherent(batch, size_t(cells), transmittance);
    if (rays) *rays += cells;
    const float first = transmittance[0];
    if (first != 0.0f && first != 1.0f) return -1.0f;
    for (int c = 1; c < cells; ++c)
        if (transmittance[c] != first) return -1.0f;
    return first;
}

} // namespace

// The visible share of an environment's light, by the ratio estimator of Heitz, Hill &
// McGuire (2018): Σ w V / Σ w over the same samples, w the part's integrand weighted by MIS.
// Luminance sampling alone leaves a surface facing away from a bright sky with almost no
// sample above its horizon, and its visibility to the one or two that are (black speckles):
// cosine samples cover the hemisphere, GGX samples the glossy lobe.
EnvironmentVisibilitySums environmentVisibilitySums(const Light& light, const SurfacePoint& at,
                                                    const glm::vec3& N, const SpecularLobe* lobe,
                                                    std::uint64_t seed, int samples,
                                                    const Visibility& visibility, long long* rays) {
    EnvironmentVisibilitySums sums;
    if (!light.ibl || light.ibl->sampler.empty()) return sums;
    const EnvironmentSampler& sampler = light.ibl->sampler;
    const float NdotV = lobe ? glm::dot(N, lobe->V) : 0.0f;
    const bool glossy = lobe && NdotV > 0.0f;
    // Techniques: luminance (half), then cosine and GGX sharing the rest.
    const int nLight = (samples + 1) / 2, rest = samples - nLight;
    const int nGgx = glossy ? (rest + 1) / 2 : 0, nCosine = rest - nGgx;
    const RotatedHammersley lightSequence(seed), cosineSequence(seed ^ 0x2545f4914f6cdd1dull),
        ggxSequence(seed ^ 0x9e3779b97f4a7c15ull);
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    const float alpha = lobe ? lobe->alpha : 1.0f;
    const glm::vec3 Vlocal = lobe ? glm::vec3(glm::dot(lobe->V, t), glm::dot(lobe->V, b), NdotV)
                                  : glm::vec3(0.0f, 0.0f, 1.0f);
    const glm::vec3 k = light.color * light.intensity;
    // The GGX technique's density of wi and the lobe's D · Vis there (0 below the surface).
    auto ggx = [&](const glm::vec3& wi, float cosTheta, float& lobeValue) {
        lobeValue = 0.0f;
        if (!glossy) return 0.0f;
        const glm::vec3 H = glm::normalize(wi + lobe->V);
        const float NdotH = glm::dot(N, H);
        if (!(NdotH > 0.0f)) return 0.0f;
        lobeValue =
            ggxDistribution(NdotH, alpha) * smithGgxCorrelatedVisibility(cosTheta, NdotV, alpha);
        return ggxVisibleNormalReflectionPdf(NdotV, NdotH, alpha);
    };
    constexpr int kBatch = 64;
    thread_local ShadowRay batch[kBatch];
    float diffuseWeight[kBatch], specularWeight[kBatch], occluderShare[kBatch],
        skyLuminance[kBatch], transmittance[kBatch];
    for (int begin = 0; begin < samples; begin += kBatch) {
        int n = 0;
        for (int i = begin; i < std::min(samples, begin + kBatch); ++i) {
            glm::vec3 wi, radiance;
            float pLight = 0.0f;
            int technique; // 0 luminance, 1 cosine, 2 GGX
            if (i < nLight) {
                technique = 0;
                const glm::vec3 d = sampler.sample(
                    lightSequence(std::uint32_t(i), std::uint32_t(nLight)), pLight, radiance);
                wi = fromEnvironment(light, d);
            } else if (i < nLight + nCosine) {
                technique = 1;
                const int j = i - nLight;
                const glm::vec3 h =
                    cosineHemisphere(cosineSequence(std::uint32_t(j), std::uint32_t(nCosine)));
                wi = glm::normalize(h.x * t + h.y * b + h.z * N);
            } else {
                technique = 2;
                const int j = i - nLight - nCosine;
                const glm::vec3 h = sampleGgxVisibleNormal(
                    Vlocal, alpha, ggxSequence(std::uint32_t(j), std::uint32_t(nGgx)));
                const glm::vec3 H = glm::normalize(h.x * t + h.y * b + h.z * N);
                wi = 2.0f * glm::dot(lobe->V, H) * H - lobe->V;
            }
            const float cosTheta = glm::dot(N, wi);
            if (!(cosTheta > 0.0f) || !(glm::dot(at.Ng, wi) > 0.0f)) continue;
            if (technique != 0) pLight = sampler.lookup(intoEnvironment(light, wi), radiance);
            if (technique == 0 && !(pLight > 0.0f)) continue;
            const float pCosine = cosTheta / kPi;
            float lobeValue;
            const float pGgx = ggx(wi, cosTheta, lobeValue);
            // Power heuristic over the three techniques: (n_t p_t)² / Σ (n_k p_k)², divided
            // by the technique's n_t p_t.
            const float a = float(nLight) * pLight, c = float(nCosine) * pCosine,
                        g = float(nGgx) * pGgx;
            const float own = technique == 0 ? a : technique == 1 ? c : g;
            if (!(own > 0.0f)) continue;
            const float mis = own / (a * a + c * c + g * g);
            const float y = luminance(radiance * k);
            diffuseWeight[n] = y * cosTheta * mis;
            specularWeight[n] = y * lobeValue * cosTheta * mis;
            skyLuminance[n] = y;
            // Black sky weighs nothing either way: not traced.
            if (!(diffuseWeight[n] > 0.0f) && !(specularWeight[n] > 0.0f)) continue;
            batch[n++] = {offsetRayOrigin(at, wi), wi, INFINITY};
        }
        visibility.test(batch, size_t(n), transmittance);
        if (rays) *rays += n;
        for (int i = 0; i < n; ++i) {
            // A blocked glossy sample's occluder: luminance ρ E(−l) / π against the sky's y.
            // Only a blocked sample reads it (it weighs 1 − v), so open ones skip the SH.
            occluderShare[i] = 0.0f;
            if (glossy && lobe->occluderAlbedo > 0.0f && specularWeight[i] > 0.0f &&
                transmittance[i] < 1.0f)
                occluderShare[i] =
                    lobe->occluderAlbedo / kPi *
                    luminance(light.ibl->irradiance(intoEnvironment(light, -batch[i].direction)) *
                              k) /
                    skyLuminance[i];
            const auto add = [&](RatioSums& r, float w, float blocked) {
                if (!(w > 0.0f) || !std::isfinite(w)) return;
                const double v = transmittance[i];
                r.total += w;
                r.seen += w * (v + (1.0 - v) * double(blocked));
                ++r.count;
                r.open += transmittance[i] == 1.0f;
            };
            add(sums.diffuse, diffuseWeight[i], 0.0f);
            if (glossy) add(sums.specular, specularWeight[i], occluderShare[i]);
        }
    }
    return sums;
}

float lightVisibility(const Light& light, const SurfacePoint& at, const glm::vec3& N,
                      std::uint64_t seed, int samples, const Visibility& visibility,
                      long long* rays) {
    if (isAmbient(light)) return 1.0f;
    if (isEnvironment(light))
        return environmentVisibilitySums(light, at, N, nullptr, seed, samples, visibility, rays)
            .diffuse.ratio();
    const bool disk = hasSunDisk(light);
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
    if (disk) {
        // Where nothing can lie towards the disk (the scene's bounds behind the point), every
        // ray would be open: the same 1 without them. The rays leave within the offset of
        // offsetRayOrigin (and an ulp per coordinate) of P.
        const float offset =
            at.error * (std::abs(at.Ng.x) + std::abs(at.Ng.y) + std::abs(at.Ng.z)) +
            1e-6f * (1.0f + std::max({std::abs(at.P.x), std::abs(at.P.y), std::abs(at.P.z)}));
        if (!visibility.mayBlockCone(at.P, offset, -light.direction, 0.5f * light.angle))
            return 1.0f;
        const float decided = sunDiskProbe(light, at, N, sequence, samples, visibility, rays);
        if (decided >= 0.0f) return decided;
    }
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
        // A sun's rays leave one point within half a degree of each other: traced together
        // (2.1× the rays a second, dhdr-bench-occlusion). An area light's spread more.
        if (disk)
            visibility.testCoherent(batch, size_t(n), transmittance);
        else
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
