// Global tone curves: each maps scene-linear values to display-linear [0, 1], written the way
// its paper or specification writes it.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

namespace dhdr {

// Hable's filmic curve ("Uncharted 2"), with its published constants.
struct HableParams {
    float shoulderStrength = 0.15f; // A
    float linearStrength = 0.50f;   // B
    float linearAngle = 0.10f;      // C
    float toeStrength = 0.20f;      // D
    float toeNumerator = 0.02f;     // E
    float toeDenominator = 0.30f;   // F
    float linearWhite = 11.2f;      // W
    float exposureBias = 2.0f;
};

// f(x) = (x (A x + C B) + D E) / (x (A x + B) + D F) − E / F.
inline float hableCurve(float x, const HableParams& p) {
    const float A = p.shoulderStrength, B = p.linearStrength, C = p.linearAngle, D = p.toeStrength,
                E = p.toeNumerator, F = p.toeDenominator;
    return (x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F) - E / F;
}

// Per channel: f(bias · x) / f(W).
inline float hable(float x, const HableParams& p) {
    return hableCurve(p.exposureBias * std::max(x, 0.0f), p) / hableCurve(p.linearWhite, p);
}

// Drago et al. 2003, eq. 4: adaptive logarithmic mapping of world luminance Lw (in units of
// the world adaptation luminance) with the largest Lwmax, bias b, display maximum Ldmax.
inline double dragoCurve(double Lw, double Lwmax, double bias = 0.85, double Ldmax = 100.0) {
    const double exponent = std::log(bias) / std::log(0.5);
    return (Ldmax * 0.01 / std::log10(Lwmax + 1.0)) * std::log(Lw + 1.0) /
           std::log(2.0 + 8.0 * std::pow(Lw / Lwmax, exponent));
}

// Khronos PBR Neutral tone mapper (2024 specification), on linear Rec.709 RGB.
inline glm::vec3 pbrNeutral(glm::vec3 color) {
    constexpr float startCompression = 0.8f - 0.04f;
    constexpr float desaturation = 0.15f;
    const float x = std::min(color.r, std::min(color.g, color.b));
    const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
    color -= offset;
    const float peak = std::max(color.r, std::max(color.g, color.b));
    if (peak < startCompression) return color;
    constexpr float d = 1.0f - startCompression;
    const float newPeak = 1.0f - d * d / (peak + d - startCompression);
    color *= newPeak / peak;
    const float g = 1.0f - 1.0f / (desaturation * (peak - newPeak) + 1.0f);
    return glm::mix(color, glm::vec3(newPeak), g);
}

// AgX (Troy Sobotka's), in Benjamin Wrensch's widely used polynomial form for sRGB primaries:
// an inset matrix, log2 encoding between −12.47393 and +4.026069 EV, a 6th-degree sigmoid fit,
// the outset matrix and a 2.2 power back to display-linear.
inline glm::vec3 agx(const glm::vec3& rgb) {
    // Column-major, as glm (and GLSL) construct matrices.
    const glm::mat3 inset(0.842479062253094f, 0.0423282422610123f, 0.0423756549057051f,
                          0.0784335999999992f, 0.878468636469772f, 0.0784336f, 0.0792237451477643f,
                          0.0791661274605434f, 0.879142973793104f);
    const glm::mat3 outset(1.19687900512017f, -0.0528968517574562f, -0.0529716355144438f,
                           -0.0980208811401368f, 1.15190312990417f, -0.0980434501171241f,
                           -0.0990297440797205f, -0.0989611768448433f, 1.15107367264116f);
    constexpr float minEv = -12.47393f, maxEv = 4.026069f;
    glm::vec3 v = inset * glm::max(rgb, glm::vec3(0.0f));
    for (int c = 0; c < 3; ++c) {
        const float ev = std::clamp(std::log2(std::max(v[c], 1e-10f)), minEv, maxEv);
        const float x = (ev - minEv) / (maxEv - minEv);
        const float x2 = x * x, x4 = x2 * x2;
        v[c] = 15.5f * x4 * x2 - 40.14f * x4 * x + 31.96f * x4 - 6.868f * x2 * x + 0.4298f * x2 +
               0.1191f * x - 0.00232f;
    }
    v = outset * v;
    for (int c = 0; c < 3; ++c)
        v[c] = std::pow(std::max(v[c], 0.0f), 2.2f);
    return v;
}

} // namespace dhdr
