#include "bounce_light.h"

#include <algorithm>
#include <dhdr/deferred/sampling.h>
#include <dhdr/deferred/surface.h>
#include <glm/gtc/constants.hpp>

namespace dhdr {

namespace {

// Surfaces the bounce rays hit reflect as if at least this rough (path regularisation,
// Kaplanyan & Dachsbacher 2013; Cycles' "Filter Glossy" does the same): a glossy sphere's
// highlight of the sun, seen from the catcher by one ray in sixteen, is a caustic that no
// denoiser removes (single bright pixels); a lobe of roughness 0.5 peaks at D ≤ 1/(π 0.25²).
constexpr float kBounceMinRoughness = 0.5f;

} // namespace

glm::vec3 BounceLighting::irradiance(const SurfacePoint& at, const glm::vec3& N,
                                     std::uint64_t directions, std::int64_t hits, int samples,
                                     long long* rays) const {
    if (samples <= 0) return glm::vec3(0.0f);
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    const RotatedHammersley sequence(directions);
    glm::dvec3 sum(0.0);
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 h = cosineHemisphere(sequence(std::uint32_t(i), std::uint32_t(samples)));
        const glm::vec3 wi = glm::normalize(h.x * t + h.y * b + h.z * N);
        // Below the triangle a shading normal leans over: no surface sends light that way.
        if (!(glm::dot(at.Ng, wi) > 0.0f)) continue;
        const Ray ray{glm::dvec3(offsetRayOrigin(at, wi)), glm::dvec3(wi)};
        const RayHit hit = m_caster.intersect(ray);
        if (rays) ++*rays;
        if (!hit.hit || hit.mesh < 0) continue;
        const SurfaceSample s = surfaceAt(m_caster.scene(), ray, hit);
        // A back face is the inside of a closed mesh: dark.
        if (s.backFace) continue;
        PbrSurface surface;
        surface.baseColor = s.albedo;
        surface.roughness = std::max(s.material->roughness, kBounceMinRoughness);
        surface.metallic = s.material->metallic;
        const glm::vec3 P(s.position);
        const LitPoint point{surface, P, glm::vec3(s.normal), -wi,
                             SurfacePoint{P, glm::vec3(s.geometric), float(s.positionError)}};
        const DirectTerms lit =
            m_atHits.sum(point, SeedKey{hits, i, streamOf(SampleStream::BounceShadow)},
                         m_emissionAtHits ? s.emission : glm::vec3(0.0f), rays);
        sum += glm::dvec3(lit.total(1.0f, 1.0f));
    }
    return glm::vec3(sum * (glm::pi<double>() / double(samples)));
}

} // namespace dhdr
