// Sampling a light from a point (pbrt-v4's Light::SampleLi): where light arrives from, how
// much, and with what density, so that its visibility can be tested apart.
#pragma once

#include <glm/glm.hpp>

namespace dhdr {

struct LightLiSample {
    // Area lights and environments: radiance arriving along wi (nit, per channel). Delta
    // lights (point, spot, directional): the illuminance they give a surface facing them (lux).
    glm::vec3 L{0.0f};
    glm::vec3 wi{0.0f};    // unit, from the point towards the light
    float distance = 0.0f; // to the sampled point of the light; +∞ for a directional light
    // Density of wi per steradian; 1 for a delta light; 0 when nothing was sampled (an
    // ambient light, a point inside a sphere light, a point behind a one-sided light).
    float pdf = 0.0f;
    bool delta = false;
};

} // namespace dhdr
