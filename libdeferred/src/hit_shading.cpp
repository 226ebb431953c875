#include "hit_shading.h"

#include <algorithm>
#include <dhdr/deferred/multiple_scattering.h>
#include <dhdr/deferred/probes.h>
#include <dhdr/deferred/surface.h>

namespace dhdr {

glm::vec3 HitShading::trace(const Ray& ray, const SeedKey& key, long long* rays) const {
    const RayHit hit = m_caster.intersect(ray);
    if (rays) ++*rays;
    if (!hit.hit || hit.mesh < 0) return glm::vec3(0.0f);
    const SurfaceSample s = surfaceAt(m_caster.scene(), ray, hit);
    // A back face is the inside of a closed mesh: dark.
    if (s.backFace) return glm::vec3(0.0f);
    PbrSurface surface;
    surface.baseColor = s.albedo;
    surface.roughness = std::max(s.material->roughness, m_minRoughness);
    surface.metallic = s.material->metallic;
    surface.diffuse = m_diffuse;
    const glm::vec3 P(s.position), N(s.normal), V(-ray.direction);
    const LitPoint point{surface, P, N, V,
                         SurfacePoint{P, glm::vec3(s.geometric), float(s.positionError)}};
    glm::vec3 L = m_direct.sum(point, key, m_emissionAtHits ? s.emission : glm::vec3(0.0f), rays)
                      .total(1.0f, 1.0f);
    if (m_probes)
        L += diffuseAlbedo(surface, std::max(glm::dot(N, V), 0.0f)) / kPi *
             m_probes->irradianceAt(P, N, V);
    return L;
}

} // namespace dhdr
