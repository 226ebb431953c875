// The estimators the lighting pass's setup chose (shade_setup.h), built once per call and
// read by the per-sample stages (shade_sample.h): each light's direct light, the surfaces that
// secondary rays hit and what gathers them, the reference path tracer, the denoised estimates.
#pragma once

#include "direct/direct_lighting.h"
#include "gi/bounce_light.h"
#include "gi/hit_shading.h"
#include "gi/specular_indirect.h"
#include "integrator/filtered_estimates.h"
#include "integrator/path_tracer.h"
#include "integrator/shade_setup.h"
#include "integrator/shade_source.h"

#include <optional>

namespace dhdr {

struct ShadeEstimators {
    // For the pixels of `roi` (within source.roi) shaded by `nthreads` threads.
    ShadeEstimators(const ShadeSource& source, const LightingInputs& inputs,
                    const LightingParams& params, const ShadeSetup& setup, OIIO::ROI roi,
                    int nthreads);
    ShadeEstimators(const ShadeEstimators&) = delete;
    ShadeEstimators& operator=(const ShadeEstimators&) = delete;

    DirectLighting direct; // the pixels' lights
    DirectLighting atHits; // the lights of the surfaces that secondary rays hit
    // Those surfaces, with a scene and without the path tracer; what gathers their light: a
    // shadow catcher's bounce light and the specular indirect light.
    std::optional<HitShading> hitShading;
    std::optional<BounceLighting> bounce;
    std::optional<SpecularIndirect> specular;
    // The reference, which replaces all of the above at every sample.
    std::optional<PathTracer> tracer;
    // Denoised estimates: computed for every sample the source holds (a
    // strip's halo rows included) and filtered before the shading reads them. Always built.
    std::optional<FilteredEstimates> filtered;
};

} // namespace dhdr
