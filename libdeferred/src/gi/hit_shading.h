// The light that leaves a surface a secondary ray hits, back along the ray: its emission (when
// no light stands for it), its direct light (DirectLighting, shadowed by its own rays) and,
// with probes, their irradiance reflected diffusely. What the shadow catcher's bounce light
// (bounce_light.h) and the specular indirect light (specular_indirect.h) gather.
#pragma once

#include "direct/direct_lighting.h"

#include <dhdr/deferred/geometry/ray_caster.h>

namespace dhdr {

struct ProbeVolume;

// How rough the surfaces that secondary rays hit reflect at least (path regularisation,
// Kaplanyan & Dachsbacher 2013; Cycles' "Filter Glossy" does the same): a glossy sphere's
// highlight of the sun, seen from the shadow catcher by one ray in sixteen, is a caustic that
// no denoiser removes (single bright pixels); a lobe of roughness 0.5 peaks at
// D ≤ 1/(π 0.25²).
inline constexpr float kHitMinRoughness = 0.5f;

class HitShading {
public:
    // `direct` lights the hits; a hit's emission counts only with `emissionAtHits` (when no
    // emissive mesh is a light already); hit surfaces reflect as if at least `minRoughness`
    // rough (path regularisation against caustics that no denoiser removes).
    HitShading(const RayCaster& caster, const DirectLighting& direct, const ProbeVolume* probes,
               bool emissionAtHits, float minRoughness, DiffuseModel diffuse)
        : m_caster(caster), m_direct(direct), m_probes(probes), m_emissionAtHits(emissionAtHits),
          m_minRoughness(minRoughness), m_diffuse(diffuse) {}

    // The radiance from the closest hit of `ray` towards its origin (0 on a miss or a back
    // face); the hit's shadow rays draw `key`. `rays` (optional) counts every ray traced.
    glm::vec3 trace(const Ray& ray, const SeedKey& key, long long* rays = nullptr) const;

    const RayCaster& caster() const { return m_caster; }

private:
    const RayCaster& m_caster;
    const DirectLighting& m_direct;
    const ProbeVolume* m_probes;
    bool m_emissionAtHits;
    float m_minRoughness;
    DiffuseModel m_diffuse;
};

} // namespace dhdr
