// Lights from every direction: an environment image (ibl.h) and an ambient light, its
// uniform special case. An environment's sun is split off as a directional light (sun.h,
// punctual.h).
#pragma once

#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/lights/sample.h>
#include <dhdr/deferred/scene/lights.h>

namespace dhdr {

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

// The radiance arriving from the scene direction d (the sky seen towards d, its sun split
// off), in the light's colour and intensity; 0 without a bake.
glm::vec3 environmentRadiance(const Light& light, const glm::vec3& d);

// The diffuse and specular light an environment light reflects towards V (ibl.h, shadeIbl:
// `method`, and the pixel footprint's `spread`), in the light's colour and intensity.
IblShading shadeEnvironment(const Light& light, const PbrSurface& s, const glm::vec3& N,
                            const glm::vec3& V, IblSpecular method = IblSpecular::Auto,
                            float spread = 0.0f);

// Radiance reflected towards V under an ambient light: uniform incident radiance La,
// Lo = La · ∫ f cos dω.
glm::vec3 shadeAmbient(const Light& light, const PbrSurface& s, const glm::vec3& N,
                       const glm::vec3& V);

// A direction drawn by the environment's luminance (EnvironmentSampler), turned into the
// scene; pdf 0 when it has no sampler.
LightLiSample sampleEnvironment(const Light& light, glm::vec2 u);

} // namespace dhdr
