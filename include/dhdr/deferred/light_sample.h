// Sampling a light from a point (pbrt-v4's Light::SampleLi): where light arrives from, how
// much, and with what density, so that its visibility can be tested apart.
#pragma once

#include <dhdr/deferred/lights.h>
#include <glm/glm.hpp>

namespace dhdr {

struct LightLiSample {
    // Area lights: radiance arriving along wi (nit, per channel). Delta lights (point, spot,
    // directional): the illuminance they give a surface facing them (lux).
    glm::vec3 L{0.0f};
    glm::vec3 wi{0.0f};    // unit, from the point towards the light
    float distance = 0.0f; // to the sampled point of the light; +∞ for a directional light
    // Density of wi per steradian; 1 for a delta light; 0 when nothing was sampled (an
    // ambient light, a point inside a sphere light, a point behind a one-sided light).
    float pdf = 0.0f;
    bool delta = false;
};

// Samples `light` from the point P with u in [0, 1)². Sphere lights are sampled uniformly in
// the cone of directions they subtend (pbrt-v4 Sphere::Sample), rectangles and emissive
// meshes uniformly by area (meshes pick a triangle by area with u.x, reused within it).
// L carries the light's range window, so L / pdf weights agree with shadeLight's
// unshadowed value.
LightLiSample sampleLi(const Light& light, const glm::vec3& P, glm::vec2 u);

} // namespace dhdr
