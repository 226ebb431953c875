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
        if (s.pdf == 0.0f || !(glm::dot(N, s.wi) > 0.0f) || !leavesSurface(at, s.wi)) return -1.0f;
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

// One traced sample's weights: the diffuse and specular integrands over the MIS density, and
// the sky's luminance in its direction.
struct SampleWeights {
    float diffuse, specular, sky;
};

// The three techniques an environment's visibility is sampled with at a point: its luminance
// (half the samples), then cosine and GGX sharing the rest, weighted against each other by the
// power heuristic.
class EnvironmentTechniques {
public:
    EnvironmentTechniques(const Light& light, const glm::vec3& N, const SpecularLobe* lobe,
                          std::uint64_t seed, int samples)
        : m_light(light), m_sampler(light.ibl->sampler), m_lobe(lobe), m_N(N),
          m_NdotV(lobe ? glm::dot(N, lobe->V) : 0.0f), m_glossy(lobe && m_NdotV > 0.0f),
          m_nLight((samples + 1) / 2), m_nGgx(m_glossy ? (samples - m_nLight + 1) / 2 : 0),
          m_nCosine(samples - m_nLight - m_nGgx), m_lightSequence(seed),
          m_cosineSequence(seed ^ 0x2545f4914f6cdd1dull),
          m_ggxSequence(seed ^ 0x9e3779b97f4a7c15ull), m_alpha(lobe ? lobe->alpha : 1.0f),
          m_k(light.color * light.intensity) {
        orthonormalBasis(N, m_t, m_b);
        m_Vlocal = lobe ? glm::vec3(glm::dot(lobe->V, m_t), glm::dot(lobe->V, m_b), m_NdotV)
                        : glm::vec3(0.0f, 0.0f, 1.0f);
    }

    // A lobe facing the viewer: GGX samples, and specular sums.
    bool glossy() const { return m_glossy; }

    // Sample i's direction wi and its weights; false where it weighs nothing (below the
    // surface, or black sky either way) and is not traced.
    bool sample(int i, const SurfacePoint& at, glm::vec3& wi, SampleWeights& w) const {
        glm::vec3 radiance;
        float pLight = 0.0f;
        const int technique = direction(i, wi, radiance, pLight);
        const float cosTheta = glm::dot(m_N, wi);
        if (!(cosTheta > 0.0f) || !(glm::dot(at.Ng, wi) > 0.0f)) return false;
        if (technique != 0) pLight = m_sampler.lookup(intoEnvironment(m_light, wi), radiance);
        if (technique == 0 && !(pLight > 0.0f)) return false;
        const float pCosine = cosTheta / kPi;
        float lobeValue;
        const float pGgx = ggx(wi, cosTheta, lobeValue);
        // Power heuristic over the three techniques: (n_t p_t)² / Σ (n_k p_k)², divided by the
        // technique's n_t p_t.
        const float a = float(m_nLight) * pLight, c = float(m_nCosine) * pCosine,
                    g = float(m_nGgx) * pGgx;
        const float own = technique == 0 ? a : technique == 1 ? c : g;
        if (!(own > 0.0f)) return false;
        const float mis = own / (a * a + c * c + g * g);
        const float y = luminance(radiance * m_k);
        w.diffuse = y * cosTheta * mis;
        w.specular = y * lobeValue * cosTheta * mis;
        w.sky = y;
        // Black sky weighs nothing either way: not traced.
        return w.diffuse > 0.0f || w.specular > 0.0f;
    }

    // A blocked glossy sample's occluder: luminance ρ E(−l) / π against the sky's y. Only a
    // blocked sample reads it (it weighs 1 − v), so open ones skip the SH.
    float occluderShare(const SampleWeights& w, float transmittance,
                        const glm::vec3& direction) const {
        if (!(m_glossy && m_lobe->occluderAlbedo > 0.0f && w.specular > 0.0f &&
              transmittance < 1.0f))
            return 0.0f;
        return m_lobe->occluderAlbedo / kPi *
               luminance(m_light.ibl->irradiance(intoEnvironment(m_light, -direction)) * m_k) /
               w.sky;
    }

private:
    // Sample i's direction, and with the luminance technique its radiance and density;
    // returns its technique (0 luminance, 1 cosine, 2 GGX).
    int direction(int i, glm::vec3& wi, glm::vec3& radiance, float& pLight) const {
        if (i < m_nLight) {
            const glm::vec3 d = m_sampler.sample(
                m_lightSequence(std::uint32_t(i), std::uint32_t(m_nLight)), pLight, radiance);
            wi = fromEnvironment(m_light, d);
            return 0;
        }
        if (i < m_nLight + m_nCosine) {
            const int j = i - m_nLight;
            const glm::vec3 h =
                cosineHemisphere(m_cosineSequence(std::uint32_t(j), std::uint32_t(m_nCosine)));
            wi = glm::normalize(h.x * m_t + h.y * m_b + h.z * m_N);
            return 1;
        }
        const int j = i - m_nLight - m_nCosine;
        const glm::vec3 h = sampleGgxVisibleNormal(
            m_Vlocal, m_alpha, m_ggxSequence(std::uint32_t(j), std::uint32_t(m_nGgx)));
        const glm::vec3 H = glm::normalize(h.x * m_t + h.y * m_b + h.z * m_N);
        wi = 2.0f * glm::dot(m_lobe->V, H) * H - m_lobe->V;
        return 2;
    }

    // The GGX technique's density of wi and the lobe's D · Vis there (0 below the surface).
    float ggx(const glm::vec3& wi, float cosTheta, float& lobeValue) const {
        lobeValue = 0.0f;
        if (!m_glossy) return 0.0f;
        const glm::vec3 H = glm::normalize(wi + m_lobe->V);
        const float NdotH = glm::dot(m_N, H);
        if (!(NdotH > 0.0f)) return 0.0f;
        lobeValue = ggxDistribution(NdotH, m_alpha) *
                    smithGgxCorrelatedVisibility(cosTheta, m_NdotV, m_alpha);
        return ggxVisibleNormalReflectionPdf(m_NdotV, NdotH, m_alpha);
    }

    const Light& m_light;
    const EnvironmentSampler& m_sampler;
    const SpecularLobe* m_lobe;
    const glm::vec3 m_N;
    const float m_NdotV;
    const bool m_glossy;
    const int m_nLight, m_nGgx, m_nCosine;
    const RotatedHammersley m_lightSequence, m_cosineSequence, m_ggxSequence;
    const float m_alpha;
    const glm::vec3 m_k;
    glm::vec3 m_t, m_b, m_Vlocal;
};

// A traced sample into the ratio sums: weight w, its transmittance, and what a blocked
// sample still counts (`blocked`).
void addSample(RatioSums& r, float w, float blocked, float transmittance) {
    if (!(w > 0.0f) || !std::isfinite(w)) return;
    const double v = transmittance;
    r.total += w;
    r.seen += w * (v + (1.0 - v) * double(blocked));
    ++r.count;
    r.open += transmittance == 1.0f;
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
    const EnvironmentTechniques techniques(light, N, lobe, seed, samples);
    constexpr int kBatch = 64;
    thread_local ShadowRay batch[kBatch];
    SampleWeights weights[kBatch];
    float transmittance[kBatch];
    for (int begin = 0; begin < samples; begin += kBatch) {
        int n = 0;
        for (int i = begin; i < std::min(samples, begin + kBatch); ++i) {
            glm::vec3 wi;
            if (!techniques.sample(i, at, wi, weights[n])) continue;
            batch[n++] = {offsetRayOrigin(at, wi), wi, INFINITY};
        }
        visibility.test(batch, size_t(n), transmittance);
        if (rays) *rays += n;
        for (int i = 0; i < n; ++i) {
            const float occluder =
                techniques.occluderShare(weights[i], transmittance[i], batch[i].direction);
            addSample(sums.diffuse, weights[i].diffuse, 0.0f, transmittance[i]);
            if (techniques.glossy())
                addSample(sums.specular, weights[i].specular, occluder, transmittance[i]);
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
        // offsetRayOrigin (and an ulp per coordinate) of P, or of P lifted by at most at.lift.
        const float offset =
            at.error * (std::abs(at.Ng.x) + std::abs(at.Ng.y) + std::abs(at.Ng.z)) +
            1e-6f * (1.0f + std::max({std::abs(at.P.x), std::abs(at.P.y), std::abs(at.P.z)})) +
            glm::length(at.lift);
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
            if (s.pdf == 0.0f || !(cosTheta > 0.0f) || !leavesSurface(at, s.wi)) continue;
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
