// Lights with an extent: spheres, rectangles and emissive meshes. Exact diffuse irradiance,
// and a representative point for the specular lobe with its energy normalization (Karis 2013,
// "Real Shading in Unreal Engine 4").
#pragma once

#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/lights/sample.h>
#include <dhdr/deferred/scene/lights.h>

namespace dhdr {

// Irradiance at a point with normal N from a sphere of unit radiance centred at `toCentre`
// (centre minus point) with the given radius, the part below the horizon cut away
// (Snyder 1996, as in Lagarde & de Rousiers 2014, "Moving Frostbite to PBR", eq. 19).
float sphereIrradiance(const glm::vec3& N, const glm::vec3& toCentre, float radius);

// Irradiance at a point with normal N from a convex polygon of unit radiance, given by its
// vertices relative to the point, clipped to the hemisphere above N (Lambert's formula:
// E = ½ Σ θ_i (n · γ_i) over the edges).
float polygonIrradiance(const glm::vec3& N, const glm::vec3* vertices, int count);

// The four corners of a rectangle light, counter-clockwise seen from the side it emits to.
void rectangleCorners(const Light& light, glm::vec3 corners[4]);

// ∫ cos⁺θ dω over the directions from P (normal N) that sampleAreaLight draws on the light:
// its irradiance at unit radiance, before the range window. The mean of cos θ / pdf over
// sampleAreaLight's samples, so that each sample's share of it weighs a shadow ray.
float areaLightIrradiance(const Light& light, const glm::vec3& P, const glm::vec3& N);

// Radiance reflected towards V from a sphere, rectangle or mesh light at a surface point: the
// diffuse lobe from the exact irradiance, the specular lobe from the point of the light
// nearest the reflected ray, scaled by (α / α′)² with α′ = min(1, α + r / (2 d)) so that the
// widened highlight keeps the energy of the point light's. Both fade with the range window of
// the distance to the light's centre.
glm::vec3 shadeAreaLight(const Light& light, const PbrSurface& s, const glm::vec3& P,
                         const glm::vec3& N, const glm::vec3& V);

// A point of the light seen from P with u in [0, 1)²: spheres uniformly in the cone of
// directions they subtend (pbrt-v4 Sphere::Sample), rectangles and meshes uniformly by area
// (meshes pick a triangle by area with u.x, reused within it). L carries the range window.
LightLiSample sampleAreaLight(const Light& light, const glm::vec3& P, glm::vec2 u);

} // namespace dhdr
