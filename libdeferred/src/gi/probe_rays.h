// A probe's rays in the bake (probe_bake.cpp): each traced once through the scene — what it
// meets, that surface's direct light, where a glossy surface's lobe leads — and shaded again
// at every bounce with the last round's probes.
#pragma once

#include "direct/direct_lighting.h"

#include <cstdint>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/geometry/surface.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/scene/lights.h>
#include <vector>

namespace dhdr {

struct Scene;

// Where a glossy hit's lobe leads: one GGX visible-normal sample. Its radiance at a bounce is
// weight × (fixed + reflectance × E / π at the next hit).
struct GlossyContinuation {
    glm::vec3 weight{0.0f}; // f cos / pdf of the sample (the single-scattering lobe)
    bool hit = false;
    glm::vec3 position{0.0f}, normal{0.0f}, towards{0.0f}, reflectance{0.0f}, fixed{0.0f};
};

// What one of a probe's rays found.
struct ProbeRay {
    bool hit = false, backFace = false;
    float distance = 0.0f;
    // What the hit reflects of the irradiance there, towards the probe (ProbeRayTracer).
    glm::vec3 position{0.0f}, normal{0.0f}, reflectance{0.0f};
    glm::vec3 fixed{0.0f}; // radiance that does not change between bounces: direct + emission
    int glossy = -1;       // a glossy hit's continuation (index among its probe's), or none

    // The radiance it brings the probe from `direction`: the fixed light, plus with the last
    // round's probes (`previous`, null at the first round) what the hit and its
    // continuation reflect of their irradiance, read as the frame reads it (`scene`).
    glm::vec3 radiance(const std::vector<GlossyContinuation>& continuations,
                       const ProbeVolume* previous, const glm::vec3& direction,
                       const Visibility* scene) const;
};

// Which ray: probe p's ray i of `rays` (its continuation draws as ray i + rays).
struct ProbeRayKey {
    std::int64_t probe = 0, ray = 0, rays = 0;
};

class ProbeRayTracer {
public:
    ProbeRayTracer(const Scene& scene, const RayCaster& caster, const std::vector<Light>& lights,
                   const ProbeBakeParams& params, bool emissiveAreLights);

    // The ray from `origin` along `direction`; a glossy hit's continuation is appended to
    // `continuations`. Distances are capped at maxDistance (a miss's).
    ProbeRay trace(const glm::vec3& origin, const glm::vec3& direction, const ProbeRayKey& key,
                   float maxDistance, std::vector<GlossyContinuation>& continuations) const;

private:
    struct LitHit;
    RayHit surfaceHit(const Ray& ray, std::int64_t probe, std::int64_t index) const;
    LitHit light(const SurfaceSample& s, const glm::vec3& towards, float distance,
                 SeedKey key) const;
    glm::vec3 sky(const glm::vec3& direction) const;

    const Scene& m_scene;
    const RayCaster& m_caster;
    const std::vector<Light>& m_lights;
    std::vector<std::uint32_t> m_infinite; // infiniteLights(m_lights): what a missed ray meets
    DiffuseModel m_diffuse;
    bool m_emissiveAreLights;
    DirectLighting m_direct;
    // The angle of the cone each of a probe's rays stands for (4π / rays steradians).
    float m_spread;
};

} // namespace dhdr
