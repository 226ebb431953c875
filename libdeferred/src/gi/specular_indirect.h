// Indirect light in glossy and metallic surfaces: the lit scene they reflect (the room in a
// gold sphere), gathered by rays drawn from the GGX lobe's visible normals (Heitz 2018) and
// shaded where they hit (hit_shading.h). Rays that miss add nothing: the environment's
// reflection is its prefiltered light (ibl.h), scaled by the specular visibility it has.
#pragma once

#include "gi/hit_shading.h"

namespace dhdr {

// Surfaces whose specular lobe reflects at least this share of uniform light at their view
// angle (luminance of the albedo with multiple scattering) get rays: metals and a
// dielectric's grazing views; a rough dielectric's 4 % is left out (docs/gi.md). A surface
// that light passes (transmission) gets them whatever its lobe reflects: with its diffuse layer
// dimmed, the reflection is most of what it shows of itself (a pane showed only lights and
// environments, 0.04 of Cycles' reflection of a lit floor: bench/transmission_cycles).
inline constexpr float kSpecularIndirectAlbedo = 0.1f;

class SpecularIndirect {
public:
    explicit SpecularIndirect(const HitShading& hits) : m_hits(hits) {}

    // Whether point p's specular lobe is worth rays (kSpecularIndirectAlbedo).
    static bool applies(const LitPoint& p);

    // Whether point p's specular lobe gets rays: it is worth them, and, when there are probes,
    // it is sharper than kProbeGlossyRoughness; rougher lobes take the probes' light as the
    // bake's hits do (probes.h). Without probes every lobe worth rays gets them.
    static bool traced(const LitPoint& p, bool probes);

    // ∫ f_spec(V, l) L(hit(l)) cos θ dl over the directions that hit the scene, by `samples`
    // GGX visible-normal directions (a rotated Hammersley set of G-buffer sample k of pixel
    // (x, y)): (1/n) Σ f_spec cos / pdf · L, f_spec the specular layer of evaluateBrdf with its
    // multiple scattering. `rays` (optional) counts every ray traced.
    glm::vec3 radiance(const LitPoint& p, int x, int y, int k, int samples,
                       long long* rays = nullptr) const;

private:
    const HitShading& m_hits;
};

} // namespace dhdr
