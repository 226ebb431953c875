#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/brdf_integrals.h>
#include <dhdr/deferred/core/sampling.h>

namespace dhdr {

namespace {

// A GGX half vector about +Z for u in [0, 1)² (Walter et al. 2007, eq. 35–36).
glm::vec3 sampleGgxHalf(glm::vec2 u, float alpha) {
    const float a2 = alpha * alpha;
    const float cosTheta = std::sqrt((1.0f - u.x) / (1.0f + (a2 - 1.0f) * u.x));
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    const float phi = 2.0f * kPi * u.y;
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

} // namespace

// The GGX half vectors integrateDFG draws at a roughness: they do not depend on N·V, so a
// row of a table draws them once.
std::vector<glm::vec3> dfgHalfVectors(float roughness, int samples) {
    const float alpha = std::max(roughness * roughness, kMinAlpha);
    std::vector<glm::vec3> h(static_cast<size_t>(samples));
    for (int i = 0; i < samples; ++i)
        h[size_t(i)] =
            sampleGgxHalf(hammersley(std::uint32_t(i), std::uint32_t(samples), 0), alpha);
    return h;
}

glm::vec2 integrateDFG(float NdotV, float roughness, const std::vector<glm::vec3>& halves) {
    const float alpha = std::max(roughness * roughness, kMinAlpha);
    const glm::vec3 V(std::sqrt(std::max(0.0f, 1.0f - NdotV * NdotV)), 0.0f, NdotV);
    double x = 0.0, y = 0.0;
    for (const glm::vec3& H : halves) {
        const float VdotH = glm::dot(V, H);
        const glm::vec3 L = 2.0f * VdotH * H - V;
        if (L.z <= 0.0f || VdotH <= 0.0f) continue;
        // f cos / pdf with pdf = D (n·h) / (4 v·h): Vis · 4 (v·h) (n·l) / (n·h), F left out.
        const double g =
            double(smithGgxCorrelatedVisibility(L.z, NdotV, alpha)) * 4.0 * VdotH * L.z / H.z;
        const double m = 1.0 - VdotH, m2 = m * m;
        x += g * (m2 * m2 * m);
        y += g;
    }
    const double n = double(halves.size());
    return {float(x / n), float(y / n)};
}

glm::vec2 integrateDFG(float NdotV, float roughness, int samples) {
    return integrateDFG(NdotV, roughness, dfgHalfVectors(roughness, samples));
}

} // namespace dhdr
