#include "integrator/shade_setup.h"

#include <algorithm>
#include <dhdr/deferred/gbuffer/gbuffer.h>

namespace dhdr {

namespace {

// AO scales ambient lights, probes and environments without shadow rays; where nothing reads
// it (and no AOV asks for it), its rays are not traced.
void chooseAO(ShadeSetup& s, const LightingInputs& inputs, const LightingParams& params) {
    const std::vector<Light>& lights = inputs.lights;
    const bool environmentsTraced = s.shadowRays && params.environmentSamples > 0;
    const bool aoRead =
        params.writeAO || s.probes ||
        std::any_of(s.infinite.begin(), s.infinite.end(), [&](std::uint32_t i) {
            return isAmbient(lights[i]) || (isEnvironment(lights[i]) && !environmentsTraced);
        });
    s.aoImage = inputs.ambientOcclusion;
    s.rayTracedAO = !s.aoImage && inputs.visibility && params.aoSamples > 0 && aoRead;
    s.aoActive = s.aoImage || s.rayTracedAO;
}

DirectLightingOptions pixelLighting(const ShadeSetup& s, const LightingParams& params) {
    DirectLightingOptions o;
    o.shadows = s.shadowRays;
    o.shadowSamples = params.shadowSamples;
    o.areaLightBudget = params.areaLightBudget;
    o.environmentSamples = params.environmentSamples;
    // With probes, the environment's diffuse light comes through them (their rays see the sky
    // where nothing blocks it); its specular light stays the IBL's.
    o.environmentDiffuse = !s.probes;
    o.environmentSpecular = params.environmentSpecular;
    o.occludable = s.aoActive;
    return o;
}

// What secondary rays see (a shadow catcher's bounce light, the specular indirect light): the
// surfaces they hit lit by every light (each shadowed by one ray; environments unshadowed,
// their specular light by the split sum) and the probes.
DirectLightingOptions hitLighting(const ShadeSetup& s) {
    DirectLightingOptions o;
    o.shadows = s.shadowRays;
    o.environmentSpecular = IblSpecular::SplitSum;
    // As at the pixels: with probes, environments' diffuse light comes through them.
    o.environmentDiffuse = !s.probes;
    return o;
}

// The environment behind the surfaces, when the background or the plate shows it.
const Light* findSky(const ShadeSetup& s, const std::vector<Light>& lights,
                     const LightingParams& params) {
    if (params.environmentBackground || params.plateEnvironment)
        for (const std::uint32_t i : s.infinite)
            if (isEnvironment(lights[i]) && lights[i].ibl) return &lights[i];
    return nullptr;
}

} // namespace

ShadeSetup setUpShading(const LightingInputs& inputs, const LightingParams& params,
                        const OIIO::ImageSpec& in) {
    const std::vector<Light>& lights = inputs.lights;
    ShadeSetup s;
    s.infinite = infiniteLights(lights);
    s.sky = findSky(s, lights, params);
    s.shadowRays = params.shadows ? inputs.visibility : nullptr;
    s.probes = inputs.probes;
    chooseAO(s, inputs, params);
    s.footprint = std::any_of(s.infinite.begin(), s.infinite.end(), [&](std::uint32_t i) {
        return (isEnvironment(lights[i]) && lights[i].ibl) || hasSunDisk(lights[i]);
    });
    s.specularActive = inputs.scene && params.specularSamples > 0 && !params.pathTrace;
    s.emissionAtHits = std::none_of(lights.begin(), lights.end(), isEmissiveMesh);
    s.catcherId = float(in.get_int_attribute(gbuffer::kShadowCatcher, 0));
    s.direct = pixelLighting(s, params);
    s.atHits = hitLighting(s);
    return s;
}

} // namespace dhdr
