// Glowing surfaces as lights: every emissive mesh of a scene becomes an area light that
// dhdr-light samples with shadow rays and culls like its other local lights.
#pragma once

#include <dhdr/deferred/scene/lights.h>
#include <vector>

namespace dhdr {

struct Scene;

// How far an emissive mesh's light reaches, as a fraction: beyond the distance d at which the
// most it can give, L·A / d², has fallen to this share of π·L (what an emitter of radiance L
// filling the whole hemisphere gives), the light is culled. Its range is that distance plus
// the radius of the mesh's bounding sphere, with the smooth window of every local light.
inline constexpr float kEmitterCutoff = 1e-4f;

// One LightType::Mesh light per mesh whose material emits (emissive factor × strength, times
// the mean of its emissive texture when it has one), named after its object, in mesh order.
std::vector<Light> emissiveLights(const Scene& scene);

// The lights a scene gives a render, in the one order dhdr-light, dhdr-probes and the Python
// module use: its own punctual lights (unless `ownLights` is false: lights files replace
// them), then its emissive meshes as area lights (with `emissive`), in radiometric units with
// `radiometric` (toRadiometricUnits). `emitters` receives how many are emissive meshes.
std::vector<Light> sceneLightList(const Scene& scene, bool ownLights, bool emissive,
                                  bool radiometric, size_t* emitters = nullptr);

} // namespace dhdr
