#include "gi/hit_shading.h"

#include <algorithm>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/geometry/surface.h>
#include <dhdr/deferred/gi/probes.h>

namespace dhdr {

glm::vec3 HitShading::trace(const Ray& ray, const SeedKey& key, long long* rays) const {
    const RayHit hit = m_caster.intersect(ray);
    if (rays) ++*rays;
    if (!hit.hit || hit.mesh < 0) return glm::vec3(0.0f);
    const SurfaceSample s = surfaceAt(m_caster.scene(), ray, hit);
    // A back face is the inside of a closed mesh: dark.
    if (s.backFace) return glm::vec3(0.0f);
    PbrSurface surface = s.pbr(m_diffuse);
    surface.roughness = std::max(s.roughness, m_minRoughness);
    const glm::vec3 P(s.position), N(s.normal), V(-ray.direction);
    LitPoint point{surface, P, N, V,
                   SurfacePoint{P, glm::vec3(s.geometric), float(s.positionError)}};
    // As at the frame's pixels: with probes, a rough lobe takes their light, environments add
    // none to it (and no diffuse light: DirectLightingOptions::environmentDiffuse).
    point.specularFromProbes = m_probes && surface.roughness >= kProbeGlossyRoughness;
    glm::vec3 L = m_direct.sum(point, key, m_emissionAtHits ? s.emission : glm::vec3(0.0f), rays)
                      .total(1.0f, 1.0f);
    if (m_probes) L += m_probes->reflectedAt(surface, P, N, V, point.specularFromProbes, &m_caster);
    return L;
}

} // namespace dhdr
