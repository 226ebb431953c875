// Shadows: how much of a light's unshadowed contribution reaches a surface point.
#pragma once

#include <cstdint>
#include <dhdr/deferred/lights.h>
#include <dhdr/deferred/visibility.h>

namespace dhdr {

// The visible share of `light` at the surface point `at` with shading normal N (unit, facing
// the camera), in [0, 1]:
// - a delta light (point, spot, directional without an angle): 0 or 1 from one ray towards it;
// - a directional light with an angle: `samples` directions uniform in its cone, weighted and
//   summed like an area light's;
// - an environment light: `samples` directions, half drawn by its luminance
//   (EnvironmentSampler), half cosine-weighted about N, combined by multiple importance
//   sampling (power heuristic), each weighted by its share of the unshadowed diffuse light
//   (luminance × cos θ); the weighted sum of the visible ones over the sum of all;
// - an area light: `samples` points of it, a stratified set (Hammersley, rotated by `seed`),
//   each ray weighted by its share of the unshadowed irradiance, L cos θ / pdf; the weighted
//   sum of the visible ones over the sum of all. Exactly 1 when every ray gets through, 0 when
//   none does.
// Samples below the horizon, of N or of the triangle's own plane (at.Ng: a smooth normal at
// a silhouette or a terminator leans past it), weigh nothing and are not traced; with none
// above it the light's unshadowed value stands (1).
// Each ray starts at offsetRayOrigin(at, its direction) and stops kShadowRayShortening short
// of the light.
// `rays` (optional) counts the rays traced.
float lightVisibility(const Light& light, const SurfacePoint& at, const glm::vec3& N,
                      std::uint64_t seed, int samples, const Visibility& visibility,
                      long long* rays = nullptr);

// The sums an environment light's visibility divides (above): seen = Σ w V and total = Σ w
// over the samples traced, and how many of them there were, wholly open and wholly closed.
// The lighting pass filters seen and total over neighbouring pixels before dividing
// (denoise.h).
struct VisibilitySums {
    double seen = 0.0, total = 0.0;
    int count = 0, open = 0, closed = 0;
};
VisibilitySums environmentVisibilitySums(const Light& light, const SurfacePoint& at,
                                         const glm::vec3& N, std::uint64_t seed, int samples,
                                         const Visibility& visibility, long long* rays = nullptr);

} // namespace dhdr
