// The visibility term of light transport, tested apart from the lights (as in pbrt-v4): a
// light sample says where light comes from, and a Visibility says whether it gets through.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <glm/glm.hpp>

namespace dhdr {

// A segment from `origin` along unit `direction` up to `tmax` (may be +∞).
struct ShadowRay {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 0.0f, 1.0f};
    float tmax = 0.0f;
};

class Visibility {
public:
    virtual ~Visibility() = default;
    // transmittance[i]: the share of light that gets through rays[i] in (0, tmax), in [0, 1]:
    // 1 when nothing is in the way, 0 when an opaque surface is, the product of (1 − α) of
    // the partly transparent surfaces crossed otherwise. Safe from many threads.
    virtual void test(const ShadowRay* rays, size_t count, float* transmittance) const = 0;

    float transmittance(const ShadowRay& ray) const {
        float t = 0.0f;
        test(&ray, 1, &t);
        return t;
    }
};

// Where a ray leaving a G-buffer surface point P starts: P moved along its normal N (unit,
// on the side the ray leaves to) by a bound on P's error. P was rounded to float (½ ulp of
// its largest coordinate) after an intersection accurate to a few ulps, and N was stored as
// half; 2⁻¹⁶ of the largest coordinate (about 128 ulps) covers both with a wide margin while
// staying far below a pixel's footprint, so a lit surface never shadows itself and a block
// standing on a floor leaves no visible gap at its foot (docs/lighting.md).
inline glm::vec3 offsetRayOrigin(const glm::vec3& P, const glm::vec3& N) {
    const float scale = std::max(std::max(std::abs(P.x), std::abs(P.y)), std::abs(P.z));
    const float epsilon = std::max(scale, 1e-3f) * 0x1p-16f;
    return P + N * epsilon;
}

// How far short of a sampled point on a light a shadow ray stops, relative to the distance:
// the light's own surface (an emissive mesh, a point light set into a ceiling) must not
// count as a blocker.
inline constexpr float kShadowRayShortening = 1e-4f;

} // namespace dhdr
