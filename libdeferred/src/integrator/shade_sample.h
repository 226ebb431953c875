// One surface sample lit, in stages named as in Cycles' shade_surface.h: emission, direct
// light, ambient light and AO, indirect light (the probes', the traced glossy lobe), the
// shadow catcher; or the reference path tracer's estimate instead.
#pragma once

#include "integrator/output_plan.h"
#include "integrator/shade_estimators.h"
#include "integrator/shade_setup.h"
#include "integrator/shade_source.h"

#include <cstdint>
#include <dhdr/deferred/lights/light_culling.h>
#include <vector>

namespace dhdr {

// What the direct-light stage reads first for every candidate light, packed by field
// (structure of arrays): enough to skip a light whose range does not reach the pixel without
// touching the rest of it.
struct LightReach {
    std::vector<float> x, y, z, range2;

    explicit LightReach(const std::vector<Light>& lights);
    // False when the light's window is zero at P.
    bool reaches(std::uint32_t i, const glm::vec3& P) const {
        const float dx = x[i] - P.x, dy = y[i] - P.y, dz = z[i] - P.z;
        return dx * dx + dy * dy + dz * dz < range2[i];
    }
};

// A sample lit: its RGBA, and what it lets through of the light behind it, per channel: 1 − A
// for a surface that only covers part of the pixel; where light passes the surface
// (KHR_materials_transmission, `passes`), also its transmittance, tinted, and then A is
// 1 − the mean of `behind` (what a reader of one alpha sees of it).
struct ShadedSample {
    glm::vec4 rgba;
    glm::vec3 behind;
    bool passes = false;
};

class SampleShader {
public:
    // The pixels of `frame` (the whole frame; its tiles are `tiles`, unused with bruteForce).
    SampleShader(const ShadeSource& source, const LightingInputs& inputs,
                 const LightingParams& params, const ShadeSetup& setup,
                 const ShadeEstimators& estimators, const OutputPlan& plan,
                 const TileLightLists& tiles, OIIO::ROI frame);

    // Sample k of pixel (x, y) lit: RGBA, premultiplied by the sample's alpha in a deep
    // G-buffer (a flat pixel keeps its RGB and its coverage as A). `aovs` (optional, after A)
    // receives its AOVs; `stats` counts what was evaluated and traced.
    ShadedSample shade(int x, int y, int k, LightingStats& stats, float* aovs) const;

private:
    struct At; // the sample, and its thread's counters

    ShadedSample pathTraced(const ShadingPoint& sp, const At& at, float* aovs) const;
    float ambientOcclusion(const ShadingPoint& sp, const At& at) const;
    LitPoint litPoint(const ShadingPoint& sp, const At& at) const;
    void directLight(const ShadingPoint& sp, const LitPoint& point, const At& at, DirectTerms& lit,
                     DirectTerms& open) const;
    void addLight(std::uint32_t i, const LitPoint& point, const SeedKey& key, const At& at,
                  DirectTerms& lit, DirectTerms& open) const;
    glm::vec3 occluded(const ShadingPoint& sp, const DirectTerms& lit, float occlusion) const;
    glm::vec3 probeIndirect(const ShadingPoint& sp, const LitPoint& point, float occlusion) const;
    glm::vec3 specularIndirect(const LitPoint& point, const At& at) const;
    bool onCatcher(const At& at) const;
    glm::vec4 shadowCatcher(const ShadingPoint& sp, const glm::vec3& shaded,
                            const DirectTerms& open, const At& at) const;
    float catcherBounce(const ShadingPoint& sp, const At& at) const;
    ShadedSample premultiplied(const ShadingPoint& sp, const glm::vec3& Lo) const;

    const ShadeSource& m_source;
    const LightingInputs& m_inputs;
    const LightingParams& m_params;
    const ShadeSetup& m_setup;
    const ShadeEstimators& m_estimators;
    const FilteredEstimates& m_filtered;
    const OutputPlan& m_plan;
    const TileLightLists& m_tiles;
    const LightReach m_reach;
    OIIO::ROI m_frame;
};

} // namespace dhdr
