// What a ray hit: the shading attributes of a scene's surface at a hit, interpolated over its
// triangle (normal and base colour maps applied), as the G-buffer stores them and as the
// probes' rays see them.
#pragma once

#include <dhdr/deferred/ray_caster.h>
#include <dhdr/deferred/scene.h>

namespace dhdr {

struct SurfaceSample {
    glm::dvec3 position;
    glm::dvec3 normal;     // shading normal, facing the ray's origin (mapped by a normal map)
    glm::dvec3 geometric;  // the interpolated normal before the normal map, facing the same way
    bool backFace = false; // the ray came from behind the file's normals (inside a closed mesh)
    glm::vec3 albedo;
    glm::vec3 emission;
    const Material* material;
};

SurfaceSample surfaceAt(const Scene& scene, const Ray& ray, const RayHit& hit);

} // namespace dhdr
