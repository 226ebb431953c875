#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/lights/punctual.h>

namespace dhdr {

IncidentLight incidentLight(const Light& light, const glm::vec3& P) {
    IncidentLight in;
    if (light.type == LightType::Directional) {
        in.L = -light.direction;
        in.illuminance = light.color * light.intensity;
        return in;
    }
    const glm::vec3 toLight = light.position - P;
    const float d2 = glm::dot(toLight, toLight);
    const float d = std::sqrt(d2);
    if (d <= 0.0f) return in;
    in.L = toLight / d;
    // E = I / d² (inverse-square law) × the range window.
    float e = light.intensity * rangeWindow(d, light.range) / d2;
    if (light.type == LightType::Spot)
        e *= spotFalloff(glm::dot(-in.L, light.direction), std::cos(light.innerConeAngle),
                         std::cos(light.outerConeAngle));
    in.illuminance = light.color * e;
    return in;
}

namespace {

glm::vec3 shadeSunDisk(const Light& light, const PbrSurface& s, const glm::vec3& N,
                       const glm::vec3& V, float spread) {
    const glm::vec3 L = -light.direction;
    const float NdotL = glm::dot(N, L), NdotV = glm::dot(N, V);
    if (NdotL <= 0.0f || NdotV <= 0.0f) return glm::vec3(0.0f);
    const glm::vec3 E = light.color * light.intensity;
    const glm::vec3 Hc = glm::normalize(L + V);
    const glm::vec3 diffuse =
        diffuseBrdf(s, N, V, L, s.fresnel(std::max(glm::dot(V, Hc), 0.0f))) * NdotL;
    const float cosR = std::cos(0.5f * light.angle), sinR = std::sin(0.5f * light.angle);
    const glm::vec3 R = glm::reflect(-V, N);
    const float LdotR = glm::dot(L, R);
    glm::vec3 Ls = R;
    if (LdotR < cosR) {
        const glm::vec3 towards = R - LdotR * L;
        const float length = glm::length(towards);
        // R opposite the sun: any side of the disk is as close.
        Ls = length > 0.0f ? glm::normalize(L * cosR + towards * (sinR / length)) : L;
    }
    const float NdotLs = glm::dot(N, Ls);
    glm::vec3 specular(0.0f);
    if (NdotLs > 0.0f) {
        const glm::vec3 H = glm::normalize(Ls + V);
        const float footprint = kFootprintAlpha * spread;
        const float alpha =
            spread > 0.0f ? std::min(1.0f, std::sqrt(s.alpha() * s.alpha() + footprint * footprint))
                          : s.alpha();
        const float widened = std::min(1.0f, alpha + 0.5f * sinR);
        const float normalization = (alpha / widened) * (alpha / widened);
        specular = s.fresnel(std::max(glm::dot(V, H), 0.0f)) *
                   (ggxDistribution(std::max(glm::dot(N, H), 0.0f), alpha) *
                    smithGgxCorrelatedVisibility(NdotLs, NdotV, alpha) * normalization * NdotLs);
    }
    // Light scattered between microfacets more than once, from the disk's centre.
    specular += multipleScatteringBrdf(s, NdotV, NdotL) * NdotL;
    return (diffuse + specular) * E;
}

} // namespace

glm::vec3 shadePunctual(const Light& light, const PbrSurface& s, const glm::vec3& P,
                        const glm::vec3& N, const glm::vec3& V, float spread,
                        float footprintRadius) {
    if (light.type == LightType::Directional && light.angle > 0.0f)
        return shadeSunDisk(light, s, N, V, spread);
    const IncidentLight in = incidentLight(light, P);
    const float NdotL = glm::dot(N, in.L);
    if (NdotL <= 0.0f || in.illuminance == glm::vec3(0.0f)) return glm::vec3(0.0f);
    // Lo = f · E · cos θ, the rendering equation for a punctual light.
    glm::vec3 f = evaluateBrdf(s, N, V, in.L);
    if (spread > 0.0f || footprintRadius > 0.0f) {
        // The single-scattering lobe filtered over the footprint, as the sun's.
        const float distance =
            light.type == LightType::Directional ? INFINITY : glm::length(light.position - P);
        const float footprint =
            kFootprintAlpha * spread + (distance > 0.0f ? 0.5f * footprintRadius / distance : 0.0f);
        PbrSurface wide = s;
        wide.roughness =
            std::sqrt(std::min(1.0f, std::sqrt(s.alpha() * s.alpha() + footprint * footprint)));
        f += singleScatteringBrdf(wide, N, V, in.L) - singleScatteringBrdf(s, N, V, in.L);
    }
    return f * in.illuminance * NdotL;
}

LightLiSample samplePunctual(const Light& light, const glm::vec3& P, glm::vec2 u) {
    LightLiSample s;
    if (light.type == LightType::Directional && light.angle > 0.0f) {
        const float cosMax = std::cos(0.5f * light.angle);
        const float omega = 2.0f * kPi * (1.0f - cosMax);
        const glm::vec3 axis = -light.direction;
        glm::vec3 t, b;
        orthonormalBasis(axis, t, b);
        const glm::vec3 c = uniformCone(u, cosMax);
        s.wi = glm::normalize(c.x * t + c.y * b + c.z * axis);
        s.L = light.color * light.intensity / omega;
        s.pdf = 1.0f / omega;
        s.distance = INFINITY;
        return s;
    }
    const IncidentLight in = incidentLight(light, P);
    s.L = in.illuminance;
    s.wi = in.L;
    s.distance = light.type == LightType::Directional ? INFINITY : glm::length(light.position - P);
    s.pdf = 1.0f;
    s.delta = true;
    return s;
}

} // namespace dhdr
