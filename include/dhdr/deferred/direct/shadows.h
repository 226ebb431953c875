// Shadows: how much of a light's unshadowed contribution reaches a surface point.
#pragma once

#include <cstdint>
#include <dhdr/deferred/core/visibility.h>
#include <dhdr/deferred/scene/lights.h>

namespace dhdr {

// The visible share of `light` at the surface point `at` with shading normal N (unit, facing
// the camera), in [0, 1]:
// - a delta light (point, spot, directional without an angle): 0 or 1 from one ray towards it;
// - a directional light with an angle: `samples` directions uniform in its cone, weighted and
//   summed like an area light's;
// - an environment light: the diffuse ratio of environmentVisibilitySums (below) without a
//   specular lobe: `samples` directions, half drawn by its luminance, half cosine-weighted;
// - an area light: `samples` points of it, a stratified set (Hammersley, rotated by `seed`),
//   each ray weighted by its share of the unshadowed irradiance, L cos θ / pdf; the weighted
//   sum of the visible ones over the sum of all. Exactly 1 when every ray gets through, 0 when
//   none does.
// Samples below the horizon, of N or of the triangle's own plane (at.Ng: a smooth normal at
// a silhouette or a terminator leans past it), weigh nothing and are not traced; with none
// above it the light's unshadowed value stands (1). On a smooth-shaded triangle (at.lift) a
// sample below its plane but above N's horizon is traced from the lifted point
// (leavesSurface, docs/lighting.md#the-shadow-terminator), as a delta light's one ray is.
// Each ray starts at offsetRayOrigin(at, its direction) and stops kShadowRayShortening short
// of the light.
// `rays` (optional) counts the rays traced.
float lightVisibility(const Light& light, const SurfacePoint& at, const glm::vec3& N,
                      std::uint64_t seed, int samples, const Visibility& visibility,
                      long long* rays = nullptr);

// The shadowed light Σ c_i V_i of `count` sphere, rectangle or emissive-mesh lights at the
// surface point `at` (shading normal N), c_i their unshadowed values (shadeLight), sharing
// `samples` shadow rays (docs/lighting.md, "Many emitters"): each ray picks light i with
// probability p_i ∝ luminance(c_i) (u.x of a stratified set, Hammersley rotated by `seed`,
// rescaled within its light and passed on with u.y to sampleAreaLight) and weighs, per colour
// channel, c_i / p_i · (cos θ / pdf) / E_i, E_i = areaLightIrradiance (the weight's mean over
// light i is 1). Per channel, Σ c_i times the weighted sum of the visible rays over the sum of
// all: a ratio estimator (Heitz et al. 2018) that converges to Σ c_i V_i, V_i lightVisibility's
// limit; exactly Σ c_i when every ray gets through and 0 when none does. Samples below the
// horizon are skipped as lightVisibility skips them. `rays` (optional) counts the rays traced.
glm::vec3 sharedLightVisibility(const Light* const* lights, const glm::vec3* unshadowed,
                                size_t count, const SurfacePoint& at, const glm::vec3& N,
                                std::uint64_t seed, int samples, const Visibility& visibility,
                                long long* rays = nullptr);

// The sums a ratio estimator divides (Heitz, Hill & McGuire 2018): seen = Σ w V and
// total = Σ w over the samples traced, how many of them there were and how many got through
// wholly. The lighting pass filters seen and total over neighbouring pixels before
// dividing (denoise.h).
struct RatioSums {
    double seen = 0.0, total = 0.0;
    int count = 0, open = 0;

    // seen / total; 1 where no sample weighed anything or every one got through (the
    // unshadowed value stands).
    float ratio() const {
        if (open == count || !(total > 0.0)) return 1.0f;
        return float(seen / total);
    }
};

// What a blocked glossy sample sees until the scene is traced into reflections: a grey
// surface of this albedo (photography's middle grey) lit by the sky, radiance
// ρ · E(−l) / π with E the environment's irradiance facing back along the ray.
inline constexpr float kOccluderAlbedo = 0.18f;

// The glossy lobe whose share of an environment a surface sees: towards the viewer V (unit)
// with GGX roughness α; a blocked direction brings the light of a grey occluder of
// `occluderAlbedo` (0: none, a pure visibility).
struct SpecularLobe {
    glm::vec3 V{0.0f};
    float alpha = 1.0f;
    float occluderAlbedo = kOccluderAlbedo;
};

// An environment light's visibility at a surface point, for its diffuse and its specular
// light apart: the same samples, each weighted by the integrand of the part (luminance × cos θ
// for the diffuse, luminance × D · Vis · cos θ for the specular lobe; Fresnel, nearly constant
// over the lobe, left out). The specular sums count a blocked sample's occluder light
// (SpecularLobe::occluderAlbedo), so their ratio is the share of the unshadowed reflection
// that arrives, and may exceed 1 where the sky behind the occluder is darker than it.
// Samples: half drawn by the environment's luminance (EnvironmentSampler), the rest
// cosine-weighted about N and, with a lobe, a half of them by GGX's visible normals
// (Heitz 2018); combined by multiple importance sampling with the power heuristic (Veach 1997,
// eq. 9.13). Without a lobe the specular sums stay empty.
struct EnvironmentVisibilitySums {
    RatioSums diffuse, specular;
};
EnvironmentVisibilitySums environmentVisibilitySums(const Light& light, const SurfacePoint& at,
                                                    const glm::vec3& N, const SpecularLobe* lobe,
                                                    std::uint64_t seed, int samples,
                                                    const Visibility& visibility,
                                                    long long* rays = nullptr);

// The two ratios of environmentVisibilitySums, each 1 where its sums are empty.
struct EnvironmentVisibility {
    float diffuse = 1.0f, specular = 1.0f;
};
inline EnvironmentVisibility ratios(const EnvironmentVisibilitySums& s) {
    return {s.diffuse.ratio(), s.specular.ratio()};
}

} // namespace dhdr
