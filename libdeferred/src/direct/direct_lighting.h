// Direct light at a surface point: each light's unshadowed value (lights/light.h) times its
// visibility (shadows.h), summed into the parts that occlusion treats apart. Shared by the
// frame's shading (integrator/shade_sample.cpp) and the probe bake (probe_bake.cpp), so that a
// probe's ray sees a surface lit exactly as the camera does.
#pragma once

#include <algorithm>
#include <cstdint>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/core/visibility.h>
#include <dhdr/deferred/direct/shadows.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/scene/lights.h>
#include <vector>

namespace dhdr {

// A point to light: its material, world position, unit shading normal and unit direction
// towards the viewer, and where its shadow rays leave from.
struct LitPoint {
    const PbrSurface& surface;
    glm::vec3 P, N, V;
    SurfacePoint origin;
    // The angle the mirror directions of the point's pixel span (radians; 0: a point), for
    // environments' specular light (shadeIbl).
    float reflectionSpread = 0.0f;
    // The radius of the footprint on the surface (scene units; 0: a point), which moves the
    // direction towards a nearby light as well (shadePunctual).
    float footprintRadius = 0.0f;
    // The scene's light in the point's glossy lobe is traced (specular_indirect.h): an
    // environment's blocked glossy samples then count nothing, not a grey occluder's light.
    bool tracedSpecular = false;
    // The probes bring the light of the point's specular lobe (a rough lobe whose light is not
    // traced, kProbeGlossyRoughness): environments add no specular light there, as they add no
    // diffuse light with probes (their rays see the sky where nothing blocks it).
    bool specularFromProbes = false;
    // The material's occlusion (ShadingPoint::occlusion): scales ambient and environment light.
    float occlusion = 1.0f;
};

// The light of a surface point in the parts that occlusion treats apart: what shadows have
// already scaled (`direct`), what AO scales (`ambient`: ambient lights and environments'
// diffuse light) and what specular occlusion scales (environments' specular light).
struct DirectTerms {
    glm::vec3 direct{0.0f}, ambient{0.0f}, environmentSpecular{0.0f};

    // The sum, the occludable parts scaled by AO `ao` and specular occlusion `so`.
    glm::vec3 total(float ao, float so) const {
        return direct + (ambient * ao + environmentSpecular * so);
    }
};

struct DirectLightingOptions {
    const Visibility* shadows = nullptr; // null: every light unshadowed
    int shadowSamples = 1;               // rays per area light or sun disk, ≥ 1
    // Shadow rays a point's sphere, rectangle and emissive-mesh lights share when each taking
    // shadowSamples would trace more (sharedLightVisibility); never fewer than shadowSamples,
    // so that one light keeps its own rays. 0: each takes shadowSamples.
    int areaLightBudget = 0;
    int environmentSamples = 0; // rays per environment light; 0: unshadowed
    // Environments' diffuse light; off when probes bring it (their rays see the sky).
    bool environmentDiffuse = true;
    // How environments' specular light is integrated (ibl.h).
    IblSpecular environmentSpecular = IblSpecular::Auto;
    // Ambient and environment lights (off for the probe bake: its rays meet the environment
    // where they miss, and ambient light is added where the probes are read).
    bool lightsAtInfinity = true;
    // Ambient lights and the light of environments without shadow rays go to
    // DirectTerms::ambient and environmentSpecular, to be occluded by AO later; otherwise to
    // `direct`.
    bool occludable = false;
};

// Which sequence a light's shadow rays draw: sampleSeed(a, b, light index, stream).
// The light index of the sequence that area lights sharing a budget draw (AO is −1, a
// catcher's bounce −2, the specular indirect light −4).
inline constexpr std::int64_t kSharedShadowsLight = -5;

struct SeedKey {
    std::int64_t a = 0, b = 0, stream = 0;
};

class DirectLighting {
public:
    DirectLighting(const std::vector<Light>& lights, const DirectLightingOptions& options)
        : m_lights(lights), m_options(options) {}

    // Adds light i at p: shadowed to `lit`, unshadowed to `open` (optional). An environment
    // light's diffuse and specular light are scaled by their own visibility
    // (environmentVisibilitySums with p's lobe); `given` (optional) replaces its shadow rays by
    // visibilities estimated beforehand (the denoised estimates). `rays` (optional) counts the
    // shadow rays traced.
    void add(std::uint32_t i, const LitPoint& p, const SeedKey& key, DirectTerms& lit,
             DirectTerms* open, const EnvironmentVisibility* given = nullptr,
             long long* rays = nullptr) const;

    // Adds the area lights `lights[0..count)` at p as add() does, each with its own
    // shadowSamples rays while they take no more than budget(), else sharing that many
    // (sharedLightVisibility, seeded by light kSharedShadowsLight).
    void addAreaLights(const std::uint32_t* lights, size_t count, const LitPoint& p,
                       const SeedKey& key, DirectTerms& lit, DirectTerms* open,
                       long long* rays = nullptr) const;
    // The rays a point's area lights share: areaLightBudget, or shadowSamples if more.
    int budget() const { return std::max(m_options.areaLightBudget, m_options.shadowSamples); }
    // Whether `count` area lights at a point share the budget.
    bool sharesBudget(size_t count) const {
        return m_options.shadows && m_options.areaLightBudget > 0 &&
               count * size_t(m_options.shadowSamples) > size_t(budget());
    }

    // Le + Σ V_i L_i over every light in order, shadowed (the probe bake's hits).
    DirectTerms sum(const LitPoint& p, const SeedKey& key, const glm::vec3& emission,
                    long long* rays = nullptr) const;

    const DirectLightingOptions& options() const { return m_options; }

private:
    const std::vector<Light>& m_lights;
    DirectLightingOptions m_options;
};

} // namespace dhdr
