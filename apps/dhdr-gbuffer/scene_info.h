// `dhdr-gbuffer --info`: what a scene holds, as text for a person.
#pragma once

#include <dhdr/deferred/scene.h>
#include <string>

namespace dhdr::app {

// Bounds, objects and triangles, cameras (name, projection, field of view or height),
// lights, materials with their textures, and what the loader left out.
std::string describeScene(const Scene& scene, const std::string& path);

} // namespace dhdr::app
