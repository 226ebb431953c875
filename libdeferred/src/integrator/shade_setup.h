// The lighting pass's setup, as an integrator is set up where it is created (pbrt-v4's
// integrators, Cycles' integrator setup): what is traced, decided once per call from the
// parameters and the inputs, before any pixel is shaded.
#pragma once

#include "direct/direct_lighting.h"

#include <cstdint>
#include <dhdr/deferred/integrator/lighting_inputs.h>
#include <dhdr/deferred/integrator/lighting_params.h>
#include <dhdr/deferred/integrator/lighting_stats.h>
#include <vector>

namespace dhdr {

struct ShadeSetup {
    // The infinite lights' indices in order (infiniteLights): where the sky, the environments
    // to denoise and the light AO scales are looked for.
    std::vector<std::uint32_t> infinite;
    // The first environment light with an image, when the background or the plate shows it.
    const Light* sky = nullptr;
    const Visibility* shadowRays = nullptr; // null: shadows are off
    const ProbeVolume* probes = nullptr;
    // AO: given as an image, or traced here (when no image is given and something reads it);
    // with either, the ambient terms are summed apart and occluded (aoActive).
    const OIIO::ImageBuf* aoImage = nullptr;
    bool rayTracedAO = false;
    bool aoActive = false;
    // Environments' and suns' specular light is filtered over each flat pixel's footprint.
    bool footprint = false;
    // The specular indirect light is traced (a scene, samples, no path tracer).
    bool specularActive = false;
    // A hit's emission counts (no emissive mesh is a light already).
    bool emissionAtHits = true;
    float catcherId = 0.0f; // the shadow catcher's object id (gbuffer::kShadowCatcher); 0: none
    // How the pixels' lights and the secondary rays' hits are lit.
    DirectLightingOptions direct, atHits;
};

// The setup for shading a G-buffer of header `in` (its shadow catcher) with `inputs` and valid
// `params`.
ShadeSetup setUpShading(const LightingInputs& inputs, const LightingParams& params,
                        const OIIO::ImageSpec& in);

} // namespace dhdr
