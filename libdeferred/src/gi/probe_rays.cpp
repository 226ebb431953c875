#include "gi/probe_rays.h"

#include <algorithm>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/geometry/surface.h>
#include <dhdr/deferred/lights/light.h>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr {

namespace {

// Transparent surfaces a probe's ray may pass before it stops at the next one.
constexpr int kProbeRayLayers = 16;

DirectLightingOptions bakeOptions(const RayCaster& caster, const ProbeBakeParams& params) {
    DirectLightingOptions o;
    o.shadows = &caster;
    o.shadowSamples = params.shadowSamples;
    o.lightsAtInfinity = false; // the sky reaches the hits through the probes
    return o;
}

} // namespace

// A surface a ray meets, seen from `towards`: its direct light with shadows and the emission
// no light stands for (fixed), and what it reflects of the irradiance there.
struct ProbeRayTracer::LitHit {
    PbrSurface surface;
    glm::vec3 reflectance{0.0f}, fixed{0.0f};
};

ProbeRayTracer::ProbeRayTracer(const Scene& scene, const RayCaster& caster,
                               const std::vector<Light>& lights, const ProbeBakeParams& params,
                               bool emissiveAreLights)
    : m_scene(scene), m_caster(caster), m_lights(lights), m_infinite(infiniteLights(lights)),
      m_diffuse(params.diffuse), m_emissiveAreLights(emissiveAreLights),
      m_direct(lights, bakeOptions(caster, params)),
      m_spread(2.0f * std::acos(1.0f - 2.0f / float(std::max(params.rays, 2)))) {}

// The surface a probe's ray stops at: it passes Mask cut-outs, and a Blend surface of coverage
// α with probability 1 − α (by a hash of the probe, ray and layer), as occlusion rays pass it
// by transmittance 1 − α: the probes see through glass by its coverage.
RayHit ProbeRayTracer::surfaceHit(const Ray& ray, std::int64_t probe, std::int64_t index) const {
    RayHit hit = m_caster.intersect(ray);
    for (int layer = 0; hit.hit && hit.mesh >= 0 && layer < kProbeRayLayers; ++layer) {
        const SurfaceCoverage c =
            surfaceCoverage(m_scene, hit.mesh, hit.triangle, float(hit.u), float(hit.v));
        if (c.present && c.alpha >= 1.0f) break;
        if (c.present && unitFloat(sampleSeed(probe, index, -1 - layer,
                                              streamOf(SampleStream::ProbeGlossy))) < c.alpha)
            break;
        // Beyond this surface: the next hit a little further along the ray.
        hit = m_caster.intersect(ray, hit.t * (1.0 + 1e-6) + 1e-6);
    }
    return hit;
}

ProbeRayTracer::LitHit ProbeRayTracer::light(const SurfaceSample& s, const glm::vec3& towards,
                                             float distance, SeedKey key) const {
    LitHit h;
    h.surface = s.pbr(m_diffuse);
    const glm::vec3 P(s.position), N(s.normal);
    const float NdotV = std::max(0.0f, glm::dot(N, towards));
    // A glossy lobe is followed along a sample: only its nearly diffuse multiple scattering
    // reflects by its albedo here.
    h.reflectance =
        diffuseAlbedo(h.surface, NdotV) + (h.surface.roughness >= kProbeGlossyRoughness
                                               ? specularAlbedo(h.surface, NdotV)
                                               : multipleScatteringAlbedo(h.surface, NdotV));
    key.stream = streamOf(SampleStream::ProbeShadow);
    // A glossy highlight is filtered over the ray's cone: narrower than the rays' spacing,
    // it would light whichever probes' rays happen to meet it (blotches on the walls).
    const LitPoint point{h.surface,
                         P,
                         N,
                         towards,
                         SurfacePoint{P, glm::vec3(s.geometric), float(s.positionError)},
                         m_spread,
                         0.5f * m_spread * distance};
    h.fixed = m_direct.sum(point, key, m_emissiveAreLights ? glm::vec3(0.0f) : s.emission).direct;
    return h;
}

glm::vec3 ProbeRayTracer::sky(const glm::vec3& direction) const {
    glm::vec3 L(0.0f);
    for (const std::uint32_t i : m_infinite)
        if (isEnvironment(m_lights[i])) L += environmentRadiance(m_lights[i], direction);
    return L;
}

ProbeRay ProbeRayTracer::trace(const glm::vec3& origin, const glm::vec3& direction,
                               const ProbeRayKey& key, float maxDistance,
                               std::vector<GlossyContinuation>& continuations) const {
    ProbeRay r;
    const Ray ray{glm::dvec3(origin), glm::dvec3(direction)};
    const RayHit hit = surfaceHit(ray, key.probe, key.ray);
    if (!hit.hit) {
        r.distance = maxDistance;
        r.fixed = sky(direction);
        return r;
    }
    const SurfaceSample s = surfaceAt(m_scene, ray, hit);
    r.hit = true;
    r.backFace = s.backFace;
    r.distance = std::min(float(hit.t), maxDistance);
    // DDGI: a back face is inside geometry: no light, and a short distance so that
    // Chebyshev's test keeps the probe from what lies behind it.
    if (r.backFace) {
        r.distance *= 0.2f;
        return r;
    }
    r.position = glm::vec3(s.position);
    r.normal = glm::vec3(s.normal);
    const glm::vec3 V = -direction, N = r.normal;
    const LitHit lit = light(s, V, float(hit.t), {key.probe, key.ray});
    r.reflectance = lit.reflectance;
    r.fixed = lit.fixed;
    const float NdotV = glm::dot(N, V);
    if (lit.surface.roughness >= kProbeGlossyRoughness || !(NdotV > 0.0f)) return r;
    // A glossy hit: its lobe's sample, traced now, is lit at every bounce.
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    const std::uint64_t seed =
        sampleSeed(key.probe, key.ray, 0, streamOf(SampleStream::ProbeGlossy));
    const glm::vec3 h = sampleGgxVisibleNormal(
        glm::vec3(glm::dot(V, t), glm::dot(V, b), NdotV), lit.surface.alpha(),
        {unitFloat(mixBits(seed)), unitFloat(mixBits(seed + 1))});
    const glm::vec3 H = glm::normalize(h.x * t + h.y * b + h.z * N);
    const glm::vec3 wi = 2.0f * glm::dot(V, H) * H - V;
    const float NdotL = glm::dot(N, wi);
    const SurfacePoint from{r.position, glm::vec3(s.geometric), float(s.positionError)};
    if (!(NdotL > 0.0f) || !(glm::dot(from.Ng, wi) > 0.0f)) return r;
    const float pdf =
        ggxVisibleNormalReflectionPdf(NdotV, std::max(glm::dot(N, H), 0.0f), lit.surface.alpha());
    if (!(pdf > 0.0f)) return r;
    GlossyContinuation c;
    c.weight = singleScatteringBrdf(lit.surface, N, V, wi) * (NdotL / pdf);
    const Ray next{glm::dvec3(offsetRayOrigin(from, wi)), glm::dvec3(wi)};
    const RayHit nextHit = surfaceHit(next, key.probe, key.ray + key.rays);
    if (!nextHit.hit) {
        c.fixed = sky(wi);
    } else if (const SurfaceSample n2 = surfaceAt(m_scene, next, nextHit); !n2.backFace) {
        const LitHit there =
            light(n2, -wi, float(hit.t + nextHit.t), {key.probe, key.ray + key.rays});
        c.hit = true;
        c.position = glm::vec3(n2.position);
        c.normal = glm::vec3(n2.normal);
        c.towards = -wi;
        // One level only: a glossy surface seen in a glossy one reflects by its albedo.
        const float mu = std::max(0.0f, glm::dot(c.normal, c.towards));
        c.reflectance = diffuseAlbedo(there.surface, mu) + specularAlbedo(there.surface, mu);
        c.fixed = there.fixed;
    }
    r.glossy = int(continuations.size());
    continuations.push_back(c);
    return r;
}

glm::vec3 ProbeRay::radiance(const std::vector<GlossyContinuation>& continuations,
                             const ProbeVolume* previous, const glm::vec3& direction,
                             const Visibility* scene) const {
    glm::vec3 L = fixed;
    if (hit && !backFace && previous)
        L += reflectance / kPi * previous->irradianceAt(position, normal, -direction, scene);
    if (glossy >= 0) {
        const GlossyContinuation& c = continuations[size_t(glossy)];
        glm::vec3 next = c.fixed;
        if (c.hit && previous)
            next += c.reflectance / kPi *
                    previous->irradianceAt(c.position, c.normal, c.towards, scene);
        L += c.weight * next;
    }
    return L;
}

} // namespace dhdr
