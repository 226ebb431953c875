// Any light, by its type: the one place that switches on it for shading and sampling. Each
// family answers the same questions in its own file: punctual.h (point, spot, directional),
// area.h (sphere, rectangle, emissive mesh), environment.h (environment, ambient).
#pragma once

#include <dhdr/deferred/lights/area.h>
#include <dhdr/deferred/lights/environment.h>
#include <dhdr/deferred/lights/punctual.h>
#include <dhdr/deferred/lights/sample.h>
#include <dhdr/deferred/scene/lights.h>

namespace dhdr {

// Radiance reflected towards V from `light` at a surface point, unshadowed. `spread` (radians):
// the angle the mirror directions of the pixel's footprint span, and `footprintRadius` (scene
// units) its radius on the surface, over which a punctual light's highlight is filtered
// (shadePunctual); 0: a point.
glm::vec3 shadeLight(const Light& light, const PbrSurface& s, const glm::vec3& P,
                     const glm::vec3& N, const glm::vec3& V, float spread = 0.0f,
                     float footprintRadius = 0.0f);

// Samples `light` from the point P with u in [0, 1)² (the family's sample function); L / pdf
// weights agree with shadeLight's unshadowed value.
LightLiSample sampleLi(const Light& light, const glm::vec3& P, glm::vec2 u);

} // namespace dhdr
