// Light that the GGX microfacets reflect more than once: the energy the single-scattering
// lobe of brdf.h loses at high roughness (a white rough metal reflects 60-70 % of the light
// at grazing view instead of all of it), returned as the lobe of Kulla & Conty 2017
// ("Revisiting Physically Based Shading at Imageworks", SIGGRAPH course): one model for every
// light, as evaluateBrdf adds it.
#pragma once

#include <dhdr/deferred/core/brdf.h>

namespace dhdr {

// The split-sum terms of the GGX lobe at (N·V, roughness) with Schlick's Fresnel, from a
// table computed once per process: x = ∫ f/F cos (1 − v·h)⁵ dω, y = E(μ) = ∫ f/F cos dω, the
// directional albedo of the lobe with F = 1. A reflectance F0 reflects F0 (y − x) + x.
glm::vec2 ggxAlbedoTerms(float NdotV, float roughness);

// E_avg = 2 ∫₀¹ E(μ) μ dμ, the cosine-weighted mean of the albedo over the view angles.
float ggxAverageAlbedo(float roughness);

// The multiple-scattering lobe (Kulla & Conty 2017, slides 17-18), in 1/sr:
//   f_ms(μo, μi) = (1 − E(μo)) (1 − E(μi)) / (π (1 − E_avg)) · F_avg² E_avg / (1 − F_avg (1 −
//   E_avg))
// with F_avg = F0 + (1 − F0) / 21, Schlick's Fresnel averaged over the cosine-weighted
// hemisphere. With F = 1 it brings ∫ (f + f_ms) cos dω to exactly 1 (the white furnace); the
// last factor sums the energy that each further bounce between microfacets keeps.
glm::vec3 multipleScatteringBrdf(const PbrSurface& s, float NdotV, float NdotL);

// ∫ f_ms cos dωi under uniform incident radiance 1: (1 − E(μo)) · F_avg² E_avg / (1 − F_avg
// (1 − E_avg)). What the lobe reflects of an environment, whose irradiance E_irr then gives
// f_ms's share as this × E_irr / π (exact for a uniform sky, the lobe being nearly diffuse).
glm::vec3 multipleScatteringAlbedo(const PbrSurface& s, float NdotV);

// The diffuse layer under light from every direction. glTF's Fresnel mix gives it 1 − F(v·h)
// of the light, and with Schlick's F, 1 − F = (1 − F0)(1 − (1 − v·h)⁵): its albedo is
// c_diff (1 − F0) T(μo), T(μ) = ∫ (1 − (1 − v·h)⁵) cos θ / π dω (0.94 at normal incidence,
// from a table over μ computed once per process). So environments, ambient light and the
// probes' irradiance E reflect c_diff (1 − F0) T(N·V) E / π, exact for uniform light, as a
// directional light's evaluateBrdf does.
// Burley's diffuse (DiffuseModel::Burley) reflects c_diff B(μo, roughness) of uniform light,
// B = ∫ f_Burley/c_diff cos dω (1.0–1.5 at roughness 1: its retro-reflection), from a table
// over μ and roughness computed once per process.
float diffuseFresnelTransmission(float NdotV);
float burleyDiffuseAlbedo(float NdotV, float roughness);
// A sheen lobe (PbrSurface::sheenLobe) reflects sheenColor E_sheen(μo) of uniform light, its
// albedo (brdf.h).
inline glm::vec3 diffuseAlbedo(const PbrSurface& s, float NdotV) {
    if (s.sheenOnly) return s.sheen.color * sheenAlbedo(NdotV, s.sheen.roughness);
    if (s.diffuse == DiffuseModel::Burley)
        return s.diffuseColor() * burleyDiffuseAlbedo(NdotV, s.roughness);
    // With f90 < 1, 1 − F = (1 − F0)(1 − (1 − v·h)⁵) + (1 − f90)(1 − v·h)⁵.
    const float T = diffuseFresnelTransmission(NdotV);
    return s.diffuseColor() * (glm::vec3(1.0f) - s.F0()) * T +
           s.diffuseColor() * ((1.0f - s.f90()) * (1.0f - T));
}

// The specular layer under light from every direction: the split sum's F0 (y − x) + x plus
// the multiple-scattering lobe's albedo. A rough lobe reflects about this × E / π of an
// irradiance E (exact for uniform light).
inline glm::vec3 specularAlbedo(const PbrSurface& s, float NdotV) {
    const glm::vec2 e = ggxAlbedoTerms(NdotV, s.roughness);
    return s.lobeReflectance(e) + multipleScatteringAlbedo(s, NdotV);
}

// KHR_materials_transmission, thin walled: the share of the light from behind the surface
// that passes it towards V, per channel. The extension's base is mix(diffuse_brdf,
// specular_btdf · baseColor, transmission) under fresnel_mix, which leaves the base what the
// dielectric's lobe does not reflect (1 − its albedo, specularAlbedo); the sheen's albedo
// scaling and the coat's 1 − b dim it as they dim the base. No refraction: what lies behind
// is seen straight through, as the extension's thin-walled case says.
inline glm::vec3 transmittance(const PbrSurface& s, const glm::vec3& N, const glm::vec3& V) {
    if (s.transmission <= 0.0f) return glm::vec3(0.0f);
    PbrSurface dielectric = s.bare();
    dielectric.metallic = 0.0f;
    const float NdotV = std::min(std::abs(glm::dot(N, V)), 1.0f);
    const glm::vec3 passed = glm::max(glm::vec3(1.0f) - specularAlbedo(dielectric, NdotV), 0.0f);
    const float layers = s.sheenScaling(N, V) * (1.0f - s.coatBlend(V));
    return s.baseColor * (s.transmission * (1.0f - s.metallic) * layers) * passed;
}

} // namespace dhdr
