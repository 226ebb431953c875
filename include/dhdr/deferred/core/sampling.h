// Deterministic sample sequences for light transport: every sequence is seeded by what it is
// for (a pixel, a light, a probe) and indexed by the sample, never by a thread or a tile, so
// results are the same for any thread count and any cut of the frame into strips.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <dhdr/deferred/core/brdf.h>
#include <glm/glm.hpp>

namespace dhdr {

// SplitMix64's finalizer (Steele et al. 2014): a bijective 64-bit mix, good enough that
// neighbouring pixels get unrelated seeds.
inline std::uint64_t mixBits(std::uint64_t v) {
    v ^= v >> 30;
    v *= 0xbf58476d1ce4e5b9ull;
    v ^= v >> 27;
    v *= 0x94d049bb133111ebull;
    v ^= v >> 31;
    return v;
}

// A seed from up to four integers (pixel x, pixel y, light index, purpose).
inline std::uint64_t sampleSeed(std::int64_t a, std::int64_t b, std::int64_t c = 0,
                                std::int64_t d = 0) {
    std::uint64_t h = mixBits(std::uint64_t(a) + 0x9e3779b97f4a7c15ull);
    h = mixBits(h ^ std::uint64_t(b));
    h = mixBits(h ^ std::uint64_t(c));
    return mixBits(h ^ std::uint64_t(d));
}

// What a sequence is for: the last integer of sampleSeed after the point (pixel or probe ray)
// and the light. A deep pixel's sample k draws stream + kStreamsPerDeepSample · k, so that
// sample 0's streams are a flat pixel's.
enum class SampleStream : std::int64_t {
    Shadow = 1,           // shadow rays of a light at a G-buffer sample
    AmbientOcclusion = 2, // AO rays (light −1)
    Bounce = 3,           // rays gathering the light objects bounce onto a point (light −2)
    BounceShadow = 4,     // shadow rays at a bounce ray's hit (seeded by point, ray)
    ProbeShadow = 5,      // shadow rays of a light at a probe ray's hit (seeded by probe, ray)
    Path = 6,             // the reference path tracer's paths (seeded by pixel, path index)
    SpecularIndirect = 7, // rays gathering the scene's light in a glossy lobe (light −4)
    ProbeGlossy = 8,      // a probe ray's continuation along a glossy hit's lobe
};
// More than the streams above, so that no sample's stream is another sample's (with 4, deep
// sample 1's Bounce was sample 0's SpecularIndirect).
inline constexpr std::int64_t kStreamsPerDeepSample = 16;
static_assert(kStreamsPerDeepSample > std::int64_t(SampleStream::ProbeGlossy),
              "a deep sample's streams would overlap the next one's");
inline std::int64_t streamOf(SampleStream s, int deepSample = 0) {
    return std::int64_t(s) + kStreamsPerDeepSample * std::int64_t(deepSample);
}

// The bits of a float, for hashing it.
inline std::uint32_t floatBits(float f) {
    std::uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    return b;
}

// A float in [0, 1) from the top 24 bits.
inline float unitFloat(std::uint64_t bits) {
    return float(bits >> 40) * 0x1p-24f;
}

// Van der Corput's radical inverse in base 2.
inline float radicalInverse2(std::uint32_t i) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
    i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
    i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
    i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
    return float(i >> 8) * 0x1p-24f;
}

// A Hammersley point set (i / n, radical inverse of i), stratified in every elementary
// interval, shifted by a seed-dependent toroidal offset (Cranley-Patterson rotation) so that
// neighbouring pixels do not share their error. The offset is drawn once per set.
struct RotatedHammersley {
    float ox, oy;

    explicit RotatedHammersley(std::uint64_t seed)
        : ox(unitFloat(mixBits(seed))), oy(unitFloat(mixBits(seed ^ 0x5851f42d4c957f2dull))) {}

    // Sample i of n.
    glm::vec2 operator()(std::uint32_t i, std::uint32_t n) const {
        float x = (float(i) + 0.5f) / float(n) + ox;
        float y = radicalInverse2(i) + oy;
        // Both are in [0, 2): wrap without std::floor, a library call on baseline x86-64.
        if (x >= 1.0f) x -= 1.0f;
        if (y >= 1.0f) y -= 1.0f;
        // Keep strictly below 1 after rounding.
        return {std::min(x, 0x1.fffffep-1f), std::min(y, 0x1.fffffep-1f)};
    }
};

inline glm::vec2 hammersley(std::uint32_t i, std::uint32_t n, std::uint64_t seed) {
    return RotatedHammersley(seed)(i, n);
}

// An orthonormal basis with `n` as its third axis (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited").
inline void orthonormalBasis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    b = glm::vec3(c, sign + n.y * n.y * a, -n.y);
}

// A cosine-weighted direction about +Z (Malley's method: a uniform point of the unit disk
// lifted to the hemisphere), pdf cos θ / π.
inline glm::vec3 cosineHemisphere(glm::vec2 u) {
    const float r = std::sqrt(u.x), phi = 2.0f * kPi * u.y;
    const float x = r * std::cos(phi), y = r * std::sin(phi);
    return {x, y, std::sqrt(std::max(0.0f, 1.0f - x * x - y * y))};
}

// A direction uniform in the cone of half-angle acos(cosMax) about +Z, pdf
// 1 / (2π (1 − cosMax)) (pbrt-v4, SampleUniformCone).
inline glm::vec3 uniformCone(glm::vec2 u, float cosMax) {
    const float cosTheta = (1.0f - u.x) + u.x * cosMax;
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    const float phi = 2.0f * kPi * u.y;
    return {std::cos(phi) * sinTheta, std::sin(phi) * sinTheta, cosTheta};
}

// Smith's masking G1 of the GGX distribution for a direction at cos θ = NdotW to the normal
// (Heitz 2014, eq. 72 with Λ of GGX).
inline float smithGgxMasking(float NdotW, float alpha) {
    const float a2 = alpha * alpha;
    return 2.0f * NdotW / (NdotW + std::sqrt(a2 + (1.0f - a2) * NdotW * NdotW));
}

// A microfacet normal of the GGX distribution of roughness α seen from V (both in the
// frame whose +Z is the surface normal; V above it), distributed as the visible normals
// D_V(h) = G1(V) max(0, V·h) D(h) / (N·V) (Heitz 2018, "Sampling the GGX Distribution of
// Visible Normals", listing 1).
inline glm::vec3 sampleGgxVisibleNormal(const glm::vec3& V, float alpha, glm::vec2 u) {
    const glm::vec3 Vh = glm::normalize(glm::vec3(alpha * V.x, alpha * V.y, V.z));
    const float lensq = Vh.x * Vh.x + Vh.y * Vh.y;
    const glm::vec3 T1 = lensq > 0.0f ? glm::vec3(-Vh.y, Vh.x, 0.0f) / std::sqrt(lensq)
                                      : glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 T2 = glm::cross(Vh, T1);
    const float r = std::sqrt(u.x), phi = 2.0f * kPi * u.y;
    const float t1 = r * std::cos(phi);
    const float s = 0.5f * (1.0f + Vh.z);
    const float t2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - t1 * t1)) + s * r * std::sin(phi);
    const glm::vec3 Nh =
        t1 * T1 + t2 * T2 + std::sqrt(std::max(0.0f, 1.0f - t1 * t1 - t2 * t2)) * Vh;
    return glm::normalize(glm::vec3(alpha * Nh.x, alpha * Nh.y, std::max(0.0f, Nh.z)));
}

// The density per steradian of L = reflect(−V, h) with h drawn by sampleGgxVisibleNormal:
// D_V(h) / (4 V·h) = G1(V) D(h) / (4 N·V) (Heitz 2018, eq. 17).
inline float ggxVisibleNormalReflectionPdf(float NdotV, float NdotH, float alpha) {
    return smithGgxMasking(NdotV, alpha) * ggxDistribution(NdotH, alpha) / (4.0f * NdotV);
}

// Barycentrics (b0, b1) of a point uniform on a triangle, b2 = 1 − b0 − b1 (Heitz 2019,
// "A Low-Distortion Map Between Triangle and Square").
inline glm::vec2 uniformTriangle(glm::vec2 u) {
    float b0, b1;
    if (u.x < u.y) {
        b0 = u.x / 2.0f;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.0f;
        b0 = u.x - b1;
    }
    return {b0, b1};
}

} // namespace dhdr
