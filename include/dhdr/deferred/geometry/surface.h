// What a ray hit: the shading attributes of a scene's surface at a hit, interpolated over its
// triangle (the material's textures and vertex colours applied), as the G-buffer stores them and as
// the probes' rays see them.
#pragma once

#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr {

struct SurfaceSample {
    // On the triangle's plane: the barycentric combination of its vertices, in double.
    glm::dvec3 position;
    // Bound on the absolute error of each coordinate of `position` once rounded to float,
    // including the float arithmetic of a ray-triangle test started there (positionError).
    double positionError = 0.0;
    glm::dvec3 normal;       // shading normal, facing the ray's origin (mapped by a normal map)
    glm::dvec3 interpolated; // the interpolated normal before the normal map, facing the same way
    glm::dvec3 geometric;    // the triangle's own unit normal, facing the ray's origin
    // From `position` to the smooth surface the vertex normals describe, on the side the ray
    // came from (terminatorLift); 0 on a flat-shaded triangle.
    glm::dvec3 lift{0.0};
    bool backFace = false; // the ray came from behind the file's normals (inside a closed mesh)
    // The material there, its textures and vertex colour applied (glTF 2.0 §3.9).
    glm::vec3 albedo;                        // baseColorFactor × base-colour texture × COLOR_0
    glm::vec3 emission;                      // emissive factor × strength × emissive texture
    float roughness = 1.0f, metallic = 0.0f; // factors × metallic-roughness texture (G, B)
    float occlusion = 1.0f; // 1 + strength · (occlusion texture's R − 1); 1 without one
    // The dielectric layer's reflectance at normal and grazing incidence (Material); both 0
    // for an unlit material, whose base colour is then its emission.
    glm::vec3 dielectricF0{0.04f};
    float dielectricF90 = 1.0f;
    // KHR_materials_clearcoat: the coat's weight and roughness (factors × textures), and its
    // normal (its own normal map's, else `interpolated`); weight 0 without a coat.
    float clearcoat = 0.0f, clearcoatRoughness = 0.0f;
    glm::dvec3 clearcoatNormal{0.0};
    // KHR_materials_sheen: the sheen's colour and roughness (factors × textures); colour 0
    // without a sheen.
    glm::vec3 sheenColor{0.0f};
    float sheenRoughness = 0.0f;
    // KHR_materials_transmission: factor × texture; 0 for an opaque surface.
    float transmission = 0.0f;
    const Material* material;

    // The BSDF's parameters there, with the diffuse layer `diffuse`.
    PbrSurface pbr(DiffuseModel diffuse) const {
        PbrSurface p;
        p.baseColor = albedo;
        p.roughness = roughness;
        p.metallic = metallic;
        p.dielectricF0 = dielectricF0;
        p.dielectricF90 = dielectricF90;
        p.diffuse = diffuse;
        p.coat = {clearcoat, clearcoatRoughness, glm::vec3(clearcoatNormal)};
        p.sheen = {sheenColor, sheenRoughness};
        p.transmission = transmission;
        return p;
    }
};

// With `footprint` (uvFootprint()), texture lookups are filtered over it; without, each is
// one bilinear lookup (as secondary rays read textures).
SurfaceSample surfaceAt(const Scene& scene, const Ray& ray, const RayHit& hit,
                        const UvFootprint* footprint = nullptr);
// The same without the material's textures and vertex colours: position, its error bound,
// the normals (before any normal map) and `material`, for what needs only where the surface
// is (the next ray's origin, which side was hit).
SurfaceSample surfaceGeometryAt(const Scene& scene, const Ray& ray, const RayHit& hit);

// The error bound of a point P = Σ wᵢ pᵢ on a triangle of float vertices pᵢ, per coordinate
// (pbrt-v4 §6.8.4 bounds its own interpolation by γ₇ Σ|wᵢ pᵢ|; here P is interpolated in
// double and the bound covers what follows it):
// - rounding P to float for the G-buffer: ½ ulp, at most 2⁻²⁴ |P|;
// - the float arithmetic of Embree's test of a ray leaving P against the triangle (and its
//   coplanar neighbours): vertices less the origin, edge cross products and a dot product,
//   each rounded, with approximate reciprocals whose last bits differ between its SSE, AVX2
//   and AVX-512 kernels. Bounded by kKernelUlps ulps of the largest vertex coordinate plus
//   the triangle's extent (a tilted error in its normal moves the plane in proportion to the
//   distance from its vertices).
// - for a mesh traced as an instance (Mesh::instance, M = (A, b)): Embree takes the ray into
//   node space by the float inverse of M's float matrix and tests it against the node-space
//   triangles, which then stand where float(M) puts them rather than at the rounded world
//   vertices. Across the triangle's plane these steps round a few ulps of |P| and |b| (the
//   origin's node-space coordinates are sums of terms that large, cancelling): kKernelUlps
//   ulps of |P| + |b| more.
double positionError(const glm::dvec3& P, const glm::dvec3 vertices[3],
                     const glm::dmat4* instance = nullptr);

// Where a shadow ray from P = Σ wᵢ pᵢ on a smooth-shaded triangle starts (Hanika 2021, "Hacking
// the Shadow Terminator", Ray Tracing Gems II ch. 4, eq. 4.3): P projected onto the tangent
// plane of each vertex (pᵢ, unit nᵢ) that it lies below, the projections interpolated,
//     P' − P = Σ wᵢ max(0, (pᵢ − P)·nᵢ) nᵢ,
// returned as that offset, less any part along −`geometric` (the triangle's unit normal on the
// normals' side): it never goes below the triangle. 0 where the normals are all equal (a flat
// face) and on a concave patch, which lies above its vertices' tangent planes.
glm::dvec3 terminatorLift(const glm::dvec3 vertices[3], const glm::dvec3 normals[3],
                          const glm::dvec3& w, const glm::dvec3& P, const glm::dvec3& geometric);

// Ulps of the vertices' magnitude that Embree's float triangle test may be off by, with a
// margin of 4× over the sum of the roundings of its Möller-Trumbore / Plücker forms.
inline constexpr double kKernelUlps = 32.0;

} // namespace dhdr
