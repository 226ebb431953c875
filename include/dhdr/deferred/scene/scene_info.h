// What a scene holds, as text for a person: `dhdr-gbuffer --info` and the Python module's
// Scene.info().
#pragma once

#include <dhdr/deferred/scene/scene.h>
#include <string>

namespace dhdr {

// Bounds, objects and triangles, cameras (name, projection, field of view or height),
// lights, materials with their textures, and what the loader left out.
std::string describeScene(const Scene& scene, const std::string& path);

} // namespace dhdr
