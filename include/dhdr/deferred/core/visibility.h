// The visibility term of light transport, tested apart from the lights (as in pbrt-v4): a
// light sample says where light comes from, and a Visibility says whether it gets through.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
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
    // The same for rays that run side by side (from one point towards one small light), which
    // an implementation may trace together; the same answers as test().
    virtual void testCoherent(const ShadowRay* rays, size_t count, float* transmittance) const {
        test(rays, count, transmittance);
    }

    // Whether any ray from within `radius` of `apex`, in a direction within `halfAngle`
    // (radians) of unit `axis`, may be blocked: false only when none can, so that every such
    // ray's transmittance is 1 (a sun's disk seen from where nothing lies towards it). The
    // default: they may.
    virtual bool mayBlockCone(const glm::vec3& /*apex*/, float /*radius*/,
                              const glm::vec3& /*axis*/, float /*halfAngle*/) const {
        return true;
    }

    float transmittance(const ShadowRay& ray) const {
        float t = 0.0f;
        test(&ray, 1, &t);
        return t;
    }
};

// A surface point that secondary rays leave from, reduced to what spawning a ray needs (as
// pbrt-v4's Interaction): P, the unit geometric normal of the surface there (its triangle's,
// not the shading normal) and a bound on the absolute error of each coordinate of P, which
// covers P's rounding and the arithmetic of a later ray-triangle test near P (surfaceAt).
// On a smooth-shaded triangle also `lift`, from P to the smooth surface its vertex normals
// describe (terminatorLift, the G-buffer's Plift; never below the triangle), and the unit
// shading normal N, which decide where rays near the shadow terminator start.
struct SurfacePoint {
    glm::vec3 P{0.0f};
    glm::vec3 Ng{0.0f, 0.0f, 1.0f};
    float error = 0.0f;
    glm::vec3 lift{0.0f};
    glm::vec3 N{0.0f};
};

// The float after v towards +∞ (or −∞): std::nextafter's result for every v but NaN, by the
// bits instead of libm's general call (pbrt-v4 NextFloatUp): that call was 2 % of a frame with sky
// shadows.
inline float nextFloatUp(float v) {
    if (std::isinf(v) && v > 0.0f) return v;
    if (v == 0.0f) v = 0.0f; // −0 steps as +0
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    bits = v >= 0.0f ? bits + 1 : bits - 1;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

inline float nextFloatDown(float v) {
    return -nextFloatUp(-v);
}

// How far above the triangle's plane (the cosine Ng·w) a ray still starts from the lifted
// point: Cycles' per-object shadow_terminator_geometry_offset, whose default this is. Rays
// well above the plane need no lift, and a lifted origin would let them slip past a nearby
// occluder (a contact shadow).
inline constexpr float kTerminatorOffset = 0.1f;

// The share of `p.lift` a ray along unit w starts from (Cycles' shadow_ray_offset, in
// kernel/light/sample.h): all of it at or below the triangle's plane, fading out as Ng·w
// rises to kTerminatorOffset (sooner where N·w is small too, so that both sides of
// N·w = kTerminatorOffset agree); none for a ray below the shading normal's horizon, which the
// lift, computed for the side the surface is seen from, does not concern.
inline float terminatorLiftShare(const SurfacePoint& p, const glm::vec3& w) {
    if (p.lift == glm::vec3(0.0f)) return 0.0f;
    const float NL = glm::dot(p.N, w);
    if (!(NL > 0.0f)) return 0.0f;
    const float NgL = glm::dot(p.Ng, w), c = kTerminatorOffset;
    const float share = NL < c ? 2.0f - (NgL + NL) / c : 1.0f - NgL / c;
    return std::clamp(share, 0.0f, 1.0f);
}

// Whether a ray from `p` along unit w, above the shading normal's horizon, is traced rather than
// taken as the surface's own: one above the triangle's plane, or one below it that starts from
// the lifted point (offsetRayOrigin), which meets the triangle where the smooth surface would
// hide the light and passes its edge where it would not.
inline bool leavesSurface(const SurfacePoint& p, const glm::vec3& w) {
    return glm::dot(p.Ng, w) > 0.0f || terminatorLiftShare(p, w) > 0.0f;
}

// Where a ray leaving `p` along `w` starts: P moved off the surface along ±Ng, to the side w
// leaves to, by d = error · (|Ng.x| + |Ng.y| + |Ng.z|) (the extent of the error box along Ng),
// each coordinate then rounded one float further away from P (pbrt-v4 OffsetRayOrigin,
// Pharr, Jakob, Humphreys 4th ed. §6.8.6). The ray can then not hit the surface it leaves,
// whatever the ulps of the intersection kernel, and starts no further off than P's error.
// Near the terminator of a smooth-shaded triangle (terminatorLiftShare > 0) it starts from the
// lifted point P + share · lift instead, always on the front of the triangle (Hanika 2021;
// the error box grown by that sum's rounding): a ray that heads into the triangle is meant to
// meet it there, as the smooth surface would hide the light, and one that passes its edge
// first is lit, so that the shadow follows the curved surface rather than the facets.
inline glm::vec3 offsetRayOrigin(const SurfacePoint& p, const glm::vec3& w) {
    glm::vec3 from = p.P;
    float error = p.error;
    bool front = !(glm::dot(w, p.Ng) < 0.0f);
    if (const float share = terminatorLiftShare(p, w); share > 0.0f) {
        from = p.P + share * p.lift;
        error += 0x1p-24f * std::max({std::abs(from.x), std::abs(from.y), std::abs(from.z)});
        front = true;
    }
    const float d = error * (std::abs(p.Ng.x) + std::abs(p.Ng.y) + std::abs(p.Ng.z));
    glm::vec3 offset = d * p.Ng;
    if (!front) offset = -offset;
    glm::vec3 o = from + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.0f)
            o[i] = nextFloatUp(o[i]);
        else if (offset[i] < 0.0f)
            o[i] = nextFloatDown(o[i]);
    }
    return o;
}

// The error bound of a point whose source gave none (a G-buffer another program wrote, with
// no Perr channel): 2⁻¹⁶ (about 128 ulps) of the larger of its distance from the camera (a
// hit position's error grows with the length of the primary ray) and its largest coordinate
// (its rounding), as the float P of a renderer that reprojects depth can be this far off.
inline float fallbackPositionError(const glm::vec3& P, const glm::vec3& eye) {
    const glm::vec3 d = glm::abs(P - eye), a = glm::abs(P);
    const float scale = std::max({d.x, d.y, d.z, a.x, a.y, a.z, 1e-3f});
    return scale * 0x1p-16f;
}

// How far short of a sampled point on a light a shadow ray stops, relative to the distance:
// the light's own surface (an emissive mesh, a point light set into a ceiling) must not
// count as a blocker.
inline constexpr float kShadowRayShortening = 1e-4f;

} // namespace dhdr
