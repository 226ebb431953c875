// The reference: unbiased Monte Carlo path tracing from the G-buffer's first hits (pbrt-v4's
// PathIntegrator in shape). At every vertex, next-event estimation samples each light
// (lights/light.h, sampleLi) and a shadow ray tests it; the BRDF is sampled (cosine for its
// diffuse layer, GGX visible normals for its specular one, Heitz 2018) to continue the path,
// and lights that such a ray can meet — environments, suns with an angle, ambient light — are
// combined with their light samples by the power heuristic (Veach 1997). Russian roulette
// ends paths whose throughput has fallen. Every random number depends only on the pixel, the
// G-buffer sample, the path sample and its dimension.
#pragma once

#include "direct/direct_lighting.h"

#include <cstdint>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <vector>

namespace dhdr {

struct PathTracerOptions {
    int samples = 16; // paths per G-buffer sample
    // Bounces after the first hit: 0 gives direct light only (the light sampled at the first
    // hit, and what its BRDF-sampled rays see of the lights at infinity).
    int bounces = 8;
    DiffuseModel diffuse = DiffuseModel::Lambert; // of the surfaces paths meet
};

class PathTracer {
public:
    // `caster` traces the scene (closest hits, and shadow rays through its Visibility).
    PathTracer(const std::vector<Light>& lights, const RayCaster& caster,
               const PathTracerOptions& options);

    // The radiance that leaves `first` towards its viewer (first.V), emission excluded (the
    // caller adds the G-buffer's), the mean of options.samples paths drawn for G-buffer sample
    // k of pixel (x, y). `rays` (optional) counts every ray traced.
    glm::vec3 radiance(const LitPoint& first, int x, int y, int k, long long* rays = nullptr) const;

private:
    struct Vertex;
    class Random;

    glm::vec3 path(const LitPoint& first, Random& random, long long& rays) const;
    glm::vec3 sampleLights(const Vertex& v, Random& random, long long& rays) const;
    glm::vec3 lightsAtInfinity(const glm::vec3& wi, float bsdfPdf) const;

    const std::vector<Light>& m_lights;
    std::vector<std::uint32_t> m_infinite; // infiniteLights(m_lights): what a missed ray meets
    const RayCaster& m_caster;
    PathTracerOptions m_options;
    // A hit's emission counts only when no emissive mesh is a light (else next-event
    // estimation has it).
    bool m_emissionAtHits = true;
};

} // namespace dhdr
