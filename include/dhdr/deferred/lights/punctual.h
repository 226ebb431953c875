// Punctual lights (KHR_lights_punctual): point, spot and directional, the last with an
// optional angular diameter (a sun's disk).
#pragma once

#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/lights/sample.h>
#include <dhdr/deferred/scene/lights.h>

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

// For point, spot and directional lights (a directional light's disk as its centre).
IncidentLight incidentLight(const Light& light, const glm::vec3& P);

// Radiance reflected towards V from a point, spot or directional light at a surface point.
// A sun with an angle (a disk of angular radius r = angle / 2 and illuminance E): diffuse from
// its centre, as a point's (the disk's horizon clipping is left out); specular at the disk's
// point closest to the mirror direction R (Karis 2013, "Real Shading in Unreal Engine 4":
// representative point), energy-normalized with α' = α + sin r / 2 as the sphere lights are.
// `spread` (radians, the angle the mirror directions of the pixel's footprint span) widens the
// sun's lobe as it widens an environment's (shadeIbl): α becomes √(α² + (kFootprintAlpha ·
// spread)²), so that a mirror shows the sun spread over the pixels its disk falls in, with its
// energy, instead of in whichever pixel's centre happens to reflect it. A point or spot light
// at distance d is filtered the same way, and further by the footprint's radius r on the
// surface, which turns the direction towards the light by r / d: the half vector moves by half
// of each, so the widening is kFootprintAlpha · spread + r / (2 d).
glm::vec3 shadePunctual(const Light& light, const PbrSurface& s, const glm::vec3& P,
                        const glm::vec3& N, const glm::vec3& V, float spread = 0.0f,
                        float footprintRadius = 0.0f);

// A delta light's one direction, or for a sun with an angle a direction uniform in its cone
// (pbrt-v4 SampleUniformCone) carrying the radiance E / Ω that spreads its illuminance over it.
LightLiSample samplePunctual(const Light& light, const glm::vec3& P, glm::vec2 u);

} // namespace dhdr
