// Light arriving at a surface point from one light, in KHR_lights_punctual units.
#pragma once

#include <cmath>
#include <dhdr/deferred/area_light.h>
#include <dhdr/deferred/brdf.h>
#include <dhdr/deferred/ibl.h>
#include <dhdr/deferred/lights.h>

namespace dhdr {

// The smooth range window of KHR_lights_punctual's recommended falloff,
// (clamp(1 − (d / range)⁴, 0, 1))²: exactly zero at and beyond `range`, so a light can be
// culled there without changing the image.
inline float rangeWindow(float distance, float range) {
    if (!std::isfinite(range)) return 1.0f;
    const float r = distance / range;
    const float r2 = r * r;
    const float w = std::clamp(1.0f - r2 * r2, 0.0f, 1.0f);
    return w * w;
}

// Angular falloff of a spot light: 1 inside the inner cone, 0 outside the outer one, a
// smoothstep between them in cos θ.
inline float spotFalloff(float cosTheta, float cosInner, float cosOuter) {
    const float t =
        std::clamp((cosTheta - cosOuter) / std::max(cosInner - cosOuter, 1e-6f), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

// A light as seen from a point: unit direction towards it and the illuminance it would give a
// surface facing it (lux, per colour channel).
struct IncidentLight {
    glm::vec3 L{0.0f};
    glm::vec3 illuminance{0.0f};
};

// For point, spot and directional lights (ambient and area lights are not one direction).
inline IncidentLight incidentLight(const Light& light, const glm::vec3& P) {
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

// A direction of the scene in an environment light's own frame: the image turned by
// `rotation` about +Y (right-handed) is read at R_y(−rotation) · d.
inline glm::vec3 intoEnvironment(const Light& light, const glm::vec3& d) {
    if (light.rotation == 0.0f) return d; // the common case, without two trigonometric calls
    const float c = std::cos(light.rotation), s = std::sin(light.rotation);
    return {c * d.x - s * d.z, d.y, s * d.x + c * d.z};
}

// The inverse of intoEnvironment: a direction of the environment's image in the scene.
inline glm::vec3 fromEnvironment(const Light& light, const glm::vec3& d) {
    if (light.rotation == 0.0f) return d; // the common case, without two trigonometric calls
    const float c = std::cos(light.rotation), s = std::sin(light.rotation);
    return {c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
}

// The diffuse and specular light an environment light reflects towards V (ibl.h), in the
// light's colour and intensity.
inline IblShading shadeEnvironment(const Light& light, const PbrSurface& s, const glm::vec3& N,
                                   const glm::vec3& V) {
    IblShading r = shadeIbl(*light.ibl, s, intoEnvironment(light, N), intoEnvironment(light, V));
    const glm::vec3 k = light.color * light.intensity;
    r.diffuse *= k;
    r.specular *= k;
    return r;
}

// Radiance reflected towards V from `light` at a surface point.
// A sun with an angle (a disk of angular radius r = angle / 2 and illuminance E): diffuse from
// its centre, as a point's (the disk's horizon clipping is left out); specular at the disk's
// point closest to the mirror direction R (Karis 2013, "Real Shading in Unreal Engine 4":
// representative point), energy-normalized with α' = α + sin r / 2 as the sphere lights are.
inline glm::vec3 shadeSunDisk(const Light& light, const PbrSurface& s, const glm::vec3& N,
                              const glm::vec3& V) {
    const glm::vec3 L = -light.direction;
    const float NdotL = glm::dot(N, L), NdotV = glm::dot(N, V);
    if (NdotL <= 0.0f || NdotV <= 0.0f) return glm::vec3(0.0f);
    const glm::vec3 E = light.color * light.intensity;
    const glm::vec3 Hc = glm::normalize(L + V);
    const glm::vec3 diffuse =
        (glm::vec3(1.0f) - schlickFresnel(s.F0(), std::max(glm::dot(V, Hc), 0.0f))) *
        s.diffuseColor() * (1.0f / kPi) * NdotL;
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
        const float alpha = s.alpha();
        const float widened = std::min(1.0f, alpha + 0.5f * sinR);
        const float normalization = (alpha / widened) * (alpha / widened);
        specular = schlickFresnel(s.F0(), std::max(glm::dot(V, H), 0.0f)) *
                   (ggxDistribution(std::max(glm::dot(N, H), 0.0f), alpha) *
                    smithGgxCorrelatedVisibility(NdotLs, NdotV, alpha) * normalization * NdotLs);
    }
    return (diffuse + specular) * E;
}

inline glm::vec3 shadeLight(const Light& light, const PbrSurface& s, const glm::vec3& P,
                            const glm::vec3& N, const glm::vec3& V) {
    if (light.type == LightType::Ambient) {
        // Uniform incident radiance La: Lo = La · ∫ f cos dω, with the directional albedo
        // approximated by its value at normal incidence, c_diff (1 − F0) + F0.
        const glm::vec3 F0 = s.F0();
        return light.color * light.intensity * (s.diffuseColor() * (glm::vec3(1.0f) - F0) + F0);
    }
    if (light.type == LightType::Environment) {
        const IblShading e = shadeEnvironment(light, s, N, V);
        return e.diffuse + e.specular;
    }
    if (light.isArea()) return shadeAreaLight(light, s, P, N, V);
    if (light.type == LightType::Directional && light.angle > 0.0f)
        return shadeSunDisk(light, s, N, V);
    const IncidentLight in = incidentLight(light, P);
    const float NdotL = glm::dot(N, in.L);
    if (NdotL <= 0.0f || in.illuminance == glm::vec3(0.0f)) return glm::vec3(0.0f);
    // Lo = f · E · cos θ, the rendering equation for a punctual light.
    return evaluateBrdf(s, N, V, in.L) * in.illuminance * NdotL;
}

} // namespace dhdr
