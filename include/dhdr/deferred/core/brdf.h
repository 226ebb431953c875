// The glTF 2.0 metallic-roughness BRDF (glTF spec, Appendix B): Lambert diffuse plus a
// Cook-Torrance microfacet specular lobe with GGX distribution, height-correlated Smith
// visibility and Schlick Fresnel.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

namespace dhdr {

inline constexpr float kPi = 3.14159265358979323846f;
// Below this α the GGX lobe is narrower than float precision can integrate; glTF's
// roughness 0 is shaded as this.
inline constexpr float kMinAlpha = 1e-3f;

// GGX / Trowbridge-Reitz normal distribution, Walter et al. 2007 eq. 33.
inline float ggxDistribution(float NdotH, float alpha) {
    const float a2 = alpha * alpha;
    const float d = NdotH * NdotH * (a2 - 1.0f) + 1.0f;
    return a2 / (kPi * d * d);
}

// Height-correlated Smith visibility V = G2 / (4 N·L N·V), Heitz 2014 eq. 99.
inline float smithGgxCorrelatedVisibility(float NdotL, float NdotV, float alpha) {
    const float a2 = alpha * alpha;
    const float gv = NdotL * std::sqrt(NdotV * NdotV * (1.0f - a2) + a2);
    const float gl = NdotV * std::sqrt(NdotL * NdotL * (1.0f - a2) + a2);
    return 0.5f / (gv + gl);
}

// Schlick 1994 Fresnel approximation.
inline glm::vec3 schlickFresnel(const glm::vec3& F0, float VdotH, float f90 = 1.0f) {
    const float m = std::clamp(1.0f - VdotH, 0.0f, 1.0f);
    const float m2 = m * m;
    return F0 + (glm::vec3(f90) - F0) * (m2 * m2 * m);
}

// The luminance of linear Rec. 709 RGB (Y of CIE XYZ).
inline float luminance(const glm::vec3& c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

// The diffuse layer's model (dhdr-light and dhdr-probes --diffuse).
enum class DiffuseModel {
    // glTF 2.0's (and Filament's): Lambert, given what the specular layer does not reflect,
    // (1 − F(v·h)) c_diff / π.
    Lambert,
    // Blender 3.x Principled BSDF's (Cycles' bsdf_principled_diffuse, "full"): Burley's
    // diffuse with its retro-reflection as Burley 2015 separates it, c_diff / π ·
    // [(1 − ½F_L)(1 − ½F_V) + R_R (F_L + F_V + F_L F_V (R_R − 1))], F_x = (1 − cos θ_x)⁵,
    // R_R = roughness (1 + l·v); added under the specular layer as Blender adds it.
    Burley
};

// KHR_materials_clearcoat's layer: a GGX lobe with its own roughness and normal over the
// whole material, weighted by clearcoat · its Fresnel (fresnel_coat, IOR 1.5).
struct Clearcoat {
    float weight = 0.0f;    // clearcoatFactor × clearcoatTexture's R; 0: no coat
    float roughness = 0.0f; // clearcoatRoughnessFactor × clearcoatRoughnessTexture's G
    glm::vec3 normal{0.0f}; // unit, world space, facing the viewer as the shading normal does
};

// KHR_materials_sheen's layer: the Charlie lobe over the base, which keeps 1 − max(colour) ·
// E_sheen(N·V) of the light (the extension's albedo scaling).
struct Sheen {
    glm::vec3 color{0.0f};  // sheenColorFactor × sheenColorTexture's RGB; 0: no sheen
    float roughness = 0.0f; // sheenRoughnessFactor × sheenRoughnessTexture's A
};

// Below this sheen roughness the Charlie lobe is a sliver at grazing half vectors that the
// albedo table cannot resolve; such a sheen is shaded as this (Filament clamps alike).
inline constexpr float kMinSheenRoughness = 0.07f;

// The Charlie sheen distribution (Estevez & Kulla 2017; KHR_materials_sheen's D):
// (2 + 1/α) sin(θh)^(1/α) / (2π), α = sheenRoughness².
inline float charlieDistribution(float NdotH, float roughness) {
    const float r = std::max(roughness, kMinSheenRoughness);
    const float invAlpha = 1.0f / (r * r);
    const float sin2 = std::max(1.0f - NdotH * NdotH, 0.0f);
    return (2.0f + invAlpha) * std::pow(sin2, 0.5f * invAlpha) / (2.0f * kPi);
}

// The sheen visibility KHR_materials_sheen allows in place of Charlie's fitted one (Neubelt &
// Pettineo 2013, "Ashikhmin"): 1 / (4 (N·L + N·V − N·L N·V)).
inline float neubeltVisibility(float NdotL, float NdotV) {
    return 1.0f / (4.0f * (NdotL + NdotV - NdotL * NdotV));
}

// E_sheen(μ, roughness) = ∫ D V cos θl dω, the directional albedo of the sheen lobe with
// colour 1, from a table computed once per process (sheen_albedo.cpp).
float sheenAlbedo(float NdotV, float roughness);

// The surface a BRDF is evaluated for, in glTF's parameters.
struct PbrSurface {
    glm::vec3 baseColor{1.0f};
    float roughness = 1.0f;
    float metallic = 0.0f;
    DiffuseModel diffuse = DiffuseModel::Lambert;

    // The dielectric layer's reflectance at normal and at grazing incidence: 4 % and 1, or as
    // KHR_materials_ior and KHR_materials_specular set them (dielectric_f0 and specular_factor).
    glm::vec3 dielectricF0{0.04f};
    float dielectricF90 = 1.0f;
    Clearcoat coat;
    Sheen sheen;
    // A surface that is only KHR_materials_sheen's lobe (sheenLobe()): diffuseBrdf and
    // diffuseAlbedo return the sheen's, and its Fresnel is 0, so every specular term is 0.
    bool sheenOnly = false;
    // KHR_materials_transmission: the dielectric's base is mix(diffuse_brdf, specular_btdf ·
    // baseColor, transmission); the diffuse layer keeps 1 − transmission (diffuseColor), the
    // rest passes through (transmittance()).
    float transmission = 0.0f;

    float alpha() const { return std::max(roughness * roughness, kMinAlpha); }
    // Normal-incidence reflectance: the dielectric's, the base colour for metals.
    glm::vec3 F0() const { return glm::mix(dielectricF0, baseColor, metallic); }
    // Grazing-incidence reflectance: the dielectric's, 1 for metals.
    float f90() const { return dielectricF90 + (1.0f - dielectricF90) * metallic; }
    // Schlick's Fresnel of the surface at a half vector's cosine (glTF 2.0 Appendix B,
    // KHR_materials_specular's fresnel_mix): F0 + (f90 − F0)(1 − v·h)⁵.
    glm::vec3 fresnel(float VdotH) const { return schlickFresnel(F0(), VdotH, f90()); }
    // The reflectance of a lobe whose split-sum terms are `e` = (x, y) (ggxAlbedoTerms, the DFG
    // table): F0 (y − x) + f90 x.
    glm::vec3 lobeReflectance(const glm::vec2& e) const {
        return F0() * (e.y - e.x) + glm::vec3(e.x) * f90();
    }
    glm::vec3 diffuseColor() const {
        return baseColor * ((1.0f - metallic) * (1.0f - transmission));
    }

    bool coated() const { return coat.weight > 0.0f; }
    // fresnel_coat's layer weight towards V (KHR_materials_clearcoat, "Layering"): clearcoat ·
    // (f0 + (1 − f0)(1 − |V·Nc|)⁵), f0 = ((1 − 1.5)/(1 + 1.5))² = 0.04. The base is weighted
    // by 1 − this, whatever the light's direction.
    float coatBlend(const glm::vec3& V) const {
        if (!coated()) return 0.0f;
        const float m = std::clamp(1.0f - std::abs(glm::dot(V, coat.normal)), 0.0f, 1.0f);
        const float m2 = m * m;
        return coat.weight * (0.04f + 0.96f * (m2 * m2 * m));
    }
    // The surface under its coat.
    PbrSurface uncoated() const {
        PbrSurface b = *this;
        b.coat.weight = 0.0f;
        return b;
    }
    bool sheened() const {
        return !sheenOnly && std::max({sheen.color.r, sheen.color.g, sheen.color.b}) > 0.0f;
    }
    // KHR_materials_sheen's sheen_albedo_scaling towards V: 1 − max(sheenColor) · E_sheen(N·V),
    // the share of light the sheen leaves to the base (whatever the light's direction, as the
    // coat's blend).
    float sheenScaling(const glm::vec3& N, const glm::vec3& V) const {
        if (!sheened()) return 1.0f;
        const float m = std::max({sheen.color.r, sheen.color.g, sheen.color.b});
        return std::max(0.0f,
                        1.0f - m * sheenAlbedo(std::max(glm::dot(N, V), 0.0f), sheen.roughness));
    }
    // The surface under its coat and its sheen.
    PbrSurface bare() const {
        PbrSurface b = uncoated();
        b.sheen.color = glm::vec3(0.0f);
        return b;
    }
    // The sheen's sheen_brdf as a surface of its own: no Fresnel (no specular lobe), its
    // diffuse layer the Charlie lobe.
    PbrSurface sheenLobe() const {
        PbrSurface c;
        c.baseColor = glm::vec3(0.0f);
        c.metallic = 0.0f;
        c.dielectricF0 = glm::vec3(0.0f);
        c.dielectricF90 = 0.0f;
        c.sheen = sheen;
        c.sheenOnly = true;
        return c;
    }
    // The coat's clearcoat_brdf as a surface of its own: the GGX lobe of α = roughness² with
    // F = 1 (its Fresnel sits in coatBlend), no diffuse layer, no coat.
    PbrSurface coatLobe() const {
        PbrSurface c;
        c.baseColor = glm::vec3(1.0f);
        c.roughness = coat.roughness;
        c.metallic = 1.0f;
        return c;
    }
};

// `shade(surface, N)` (any light's or the environment's reflection, linear in the BRDF) of a
// layered surface. The sheen over the base (KHR_materials_sheen's sheen_brdf + material ·
// sheen_albedo_scaling): the bare base's × s.sheenScaling + the sheen lobe's; the coat over
// both (KHR_materials_clearcoat's mix(material, clearcoat_brdf, b)): (1 − b) × that + b ×
// the coat lobe's about the coat's normal, b = s.coatBlend(V).
template <class Shade>
auto withCoat(const PbrSurface& s, const glm::vec3& N, const glm::vec3& V, Shade shade) {
    if (!s.coated() && !s.sheened()) return shade(s, N);
    auto base = shade(s.bare(), N);
    if (s.sheened()) base = base * s.sheenScaling(N, V) + shade(s.sheenLobe(), N);
    if (!s.coated()) return base;
    const float b = s.coatBlend(V);
    return base * (1.0f - b) + shade(s.coatLobe(), s.coat.normal) * b;
}

// KHR_materials_sheen's sheen_brdf, sheenColor · D_charlie · V_neubelt, in 1/sr (N·L > 0,
// N·V > 0).
inline glm::vec3 sheenBrdf(const Sheen& sheen, const glm::vec3& N, const glm::vec3& V,
                           const glm::vec3& L) {
    const float NdotL = std::max(glm::dot(N, L), 0.0f), NdotV = std::max(glm::dot(N, V), 0.0f);
    if (NdotL <= 0.0f || NdotV <= 0.0f) return glm::vec3(0.0f);
    const float NdotH = glm::dot(N, glm::normalize(L + V));
    return sheen.color *
           (charlieDistribution(NdotH, sheen.roughness) * neubeltVisibility(NdotL, NdotV));
}

// The multiple-scattering lobe of Kulla & Conty 2017 (multiple_scattering.h).
glm::vec3 multipleScatteringBrdf(const PbrSurface& s, float NdotV, float NdotL);

// The diffuse layer's BRDF in 1/sr for light from L (N·L > 0, N·V > 0), F the specular
// layer's Fresnel reflectance at L's half vector (what glTF's Lambert layer does not get).
inline glm::vec3 diffuseBrdf(const PbrSurface& s, const glm::vec3& N, const glm::vec3& V,
                             const glm::vec3& L, const glm::vec3& F) {
    if (s.sheenOnly) return sheenBrdf(s.sheen, N, V, L);
    if (s.diffuse == DiffuseModel::Burley) {
        const float NdotL = std::max(glm::dot(N, L), 0.0f), NdotV = std::max(glm::dot(N, V), 0.0f);
        const float a = 1.0f - NdotL, b = 1.0f - NdotV;
        const float FL = a * a * a * a * a, FV = b * b * b * b * b;
        const float RR = s.roughness * (glm::dot(L, V) + 1.0f);
        const float f =
            (1.0f - 0.5f * FL) * (1.0f - 0.5f * FV) + RR * (FL + FV + FL * FV * (RR - 1.0f));
        return s.diffuseColor() * (f / kPi);
    }
    return (glm::vec3(1.0f) - F) * s.diffuseColor() * (1.0f / kPi);
}

// The single-scattering GGX lobe F D V of an uncoated surface, in 1/sr, zero below the surface.
inline glm::vec3 ggxLobe(const PbrSurface& s, const glm::vec3& N, const glm::vec3& V,
                         const glm::vec3& L, float NdotL, float NdotV) {
    const glm::vec3 H = glm::normalize(L + V);
    const float NdotH = std::max(glm::dot(N, H), 0.0f);
    const float alpha = s.alpha();
    return s.fresnel(std::max(glm::dot(V, H), 0.0f)) *
           (ggxDistribution(NdotH, alpha) * smithGgxCorrelatedVisibility(NdotL, NdotV, alpha));
}

// f(l, v) in 1/sr for unit vectors N, V (towards the viewer) and L (towards the light);
// zero when either is below the surface. The specular lobe includes the light scattered
// between microfacets more than once (multiple_scattering.h), as Blender's multiscatter GGX
// does; glTF's reference model leaves it out and loses up to a third of a rough metal's light.
// A clearcoat is layered over it (withCoat).
inline glm::vec3 evaluateBrdf(const PbrSurface& s, const glm::vec3& N, const glm::vec3& V,
                              const glm::vec3& L) {
    return withCoat(s, N, V, [&](const PbrSurface& l, const glm::vec3& n) {
        const float NdotL = glm::dot(n, L);
        const float NdotV = glm::dot(n, V);
        if (NdotL <= 0.0f || NdotV <= 0.0f) return glm::vec3(0.0f);
        const glm::vec3 F = l.fresnel(std::max(glm::dot(V, glm::normalize(L + V)), 0.0f));
        return diffuseBrdf(l, n, V, L, F) +
               (ggxLobe(l, n, V, L, NdotL, NdotV) + multipleScatteringBrdf(l, NdotV, NdotL));
    });
}

// evaluateBrdf's specular lobe alone, for light that follows the lobe, in 1/sr, zero below
// the surface: the single-scattering GGX lobe F D V (of the base and its coat).
inline glm::vec3 singleScatteringBrdf(const PbrSurface& s, const glm::vec3& N, const glm::vec3& V,
                                      const glm::vec3& L) {
    return withCoat(s, N, V, [&](const PbrSurface& l, const glm::vec3& n) {
        const float NdotL = glm::dot(n, L);
        const float NdotV = glm::dot(n, V);
        if (NdotL <= 0.0f || NdotV <= 0.0f) return glm::vec3(0.0f);
        return ggxLobe(l, n, V, L, NdotL, NdotV);
    });
}
inline glm::vec3 specularBrdf(const PbrSurface& s, const glm::vec3& N, const glm::vec3& V,
                              const glm::vec3& L) {
    return withCoat(s, N, V, [&](const PbrSurface& l, const glm::vec3& n) {
        const float NdotL = glm::dot(n, L);
        const float NdotV = glm::dot(n, V);
        if (NdotL <= 0.0f || NdotV <= 0.0f) return glm::vec3(0.0f);
        return ggxLobe(l, n, V, L, NdotL, NdotV) + multipleScatteringBrdf(l, NdotV, NdotL);
    });
}

} // namespace dhdr
