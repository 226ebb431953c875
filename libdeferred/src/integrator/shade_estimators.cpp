#include "integrator/shade_estimators.h"

namespace dhdr {

ShadeEstimators::ShadeEstimators(const ShadeSource& source, const LightingInputs& inputs,
                                 const LightingParams& params, const ShadeSetup& setup,
                                 OIIO::ROI roi, int nthreads)
    : direct(inputs.lights, setup.direct), atHits(inputs.lights, setup.atHits) {
    if (inputs.scene && !params.pathTrace)
        hitShading.emplace(*inputs.scene, atHits, setup.probes, setup.emissionAtHits,
                           kHitMinRoughness, params.diffuse);
    if (hitShading && setup.shadowRays && setup.catcherId > 0 && params.catcherBounceSamples > 0)
        bounce.emplace(*hitShading);
    if (hitShading && setup.specularActive) specular.emplace(*hitShading);
    if (params.pathTrace)
        tracer.emplace(inputs.lights, *inputs.scene,
                       PathTracerOptions{params.pathSamples, params.pathBounces, params.diffuse});
    LightingParams estimated = params;
    estimated.denoise = params.denoise && !params.pathTrace;
    filtered.emplace(source.view, source.layout, source.roi, roi, inputs.lights, setup.infinite,
                     estimated, setup.shadowRays, setup.rayTracedAO ? inputs.visibility : nullptr,
                     TracedEstimates{bounce ? &*bounce : nullptr, setup.catcherId,
                                     specular ? &*specular : nullptr, setup.probes != nullptr},
                     nthreads, inputs.carry);
}

} // namespace dhdr
