// A pixel's footprint in the textures of the surface its primary ray hit, for filtered lookups.
#pragma once

#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr {

// The footprint of a pixel on the UV sets of the triangle its ray `centre` hit: that ray and the
// rays through the neighbouring pixels across (`across`) and down (`down`) are met with the
// triangle's plane, and the differences of the neighbours' points from the centre's are taken
// into each UV set through their barycentrics
// (pbrt-v4's camera ray differentials, "Texture Sampling and Antialiasing" §10.1; on a
// triangle uv is linear in position, so the map is exact where pbrt-v4 fits one by least
// squares). A neighbour's ray that runs parallel to the plane or meets it behind its origin
// (a surface seen edge-on) makes the footprint as wide as the texture 10⁸ times over, i.e.
// its smallest mip level. On the ground plane, which has no UVs, the footprint is zero.
UvFootprint uvFootprint(const Scene& scene, const RayHit& hit, const Ray& centre, const Ray& across,
                        const Ray& down, TextureFilter filter);

} // namespace dhdr
