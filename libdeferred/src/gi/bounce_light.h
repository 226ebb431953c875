// Light that the scene's surfaces reflect onto a point: one bounce of indirect light, gathered
// by tracing rays to the surfaces around the point and lighting what they hit as the camera's
// pixels are lit (DirectLighting). A shadow catcher counts it, as Cycles' catcher does, so
// that the light objects bounce onto the ground lightens their shadow.
#pragma once

#include "gi/hit_shading.h"

#include <cstdint>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <vector>

namespace dhdr {

class BounceLighting {
public:
    // `hits` gives the light of the surfaces the rays hit.
    explicit BounceLighting(const HitShading& hits);

    // The irradiance at `at` (unit shading normal N) of the light leaving the surfaces that
    // `samples` cosine-weighted rays hit: E = ∫ L(x(ω)) cos θ dω ≈ π/n Σ L(x(ω_i)) (misses
    // add nothing: lights and the environment are the point's direct light; a direction that
    // misses the spheres round the scene's meshes is such a miss, and is not traced). The
    // directions follow `directions` (a rotated Hammersley set); hit i's shadow rays draw
    // SeedKey{hits, i, BounceShadow}. `rays` (optional) counts every ray traced.
    glm::vec3 irradiance(const SurfacePoint& at, const glm::vec3& N, std::uint64_t directions,
                         std::int64_t hits, int samples, long long* rays = nullptr) const;

    // The same for G-buffer sample k of pixel (x, y), with that sample's own sequences.
    glm::vec3 irradianceAt(const SurfacePoint& at, const glm::vec3& N, int x, int y, int k,
                           int samples, long long* rays = nullptr) const {
        return irradiance(at, N, sampleSeed(x, y, -2, streamOf(SampleStream::Bounce, k)),
                          std::int64_t(sampleSeed(x, y, -3, streamOf(SampleStream::Bounce, k))),
                          samples, rays);
    }

private:
    struct Sphere {
        glm::dvec3 centre{0.0};
        double radius = 0.0;
    };
    const HitShading& m_hits;
    bool m_empty = true; // no triangle: every ray misses
    // Spheres that hold the triangles: one per mesh when the meshes are few (a direction
    // between the objects of a scene is culled too), else one round the whole scene.
    std::vector<Sphere> m_spheres;
};

} // namespace dhdr
