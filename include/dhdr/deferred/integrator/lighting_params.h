// The choices of the lighting pass (lighting.h): what is traced, how many samples, what is
// written; their ranges and the options of dhdr-light that set them.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <atomic>
#include <dhdr/common/param_table.h>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/environment/ibl.h>
#include <string>
#include <vector>

namespace dhdr {

struct LightingParams {
    // Evaluate every light at every pixel instead of only those whose screen rectangle
    // covers the pixel's tile: the reference the culled pass must match.
    bool bruteForce = false;
    // Side of the square tiles that per-tile light lists are built for, in pixels (range:
    // kLightingParamTable).
    int tileSize = 16;
    // RGBA written where the G-buffer has no surface (A = 0).
    float background[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    // Instead, where there is no surface, the first environment light as the camera sees it
    // (full resolution, bilinear; A = 1), so that the frame is complete.
    bool environmentBackground = false;
    // Composite over the first environment light as the camera sees it (when no plate image).
    bool plateEnvironment = false;
    // G-buffer channels copied into the output after R, G, B, A (and AO) (e.g. "Z", "N.X").
    std::vector<std::string> passThrough;
    // The whole frame, when the G-buffer given is a strip of its rows (dhdr-light streams
    // frames strip by strip); undefined: the G-buffer's own pixels are the frame. Tiles are
    // laid over the frame, so a pixel's result does not depend on how the frame is cut.
    OIIO::ROI frame;
    // With a Visibility: trace shadow rays (false: the unshadowed reference, AO still traced).
    bool shadows = true;
    // Points sampled on each sphere, rectangle or emissive-mesh light per pixel for its soft
    // shadow. The counts' ranges are kLightingParamTable's (below), checked by validate().
    int shadowSamples = 16;
    // Shadow rays per pixel that the area lights reaching it share, picked by each one's
    // unshadowed light, when shadowSamples each would trace more (docs/lighting.md, "Many
    // emitters"); shadowSamples when that is more; 0: every area light takes shadowSamples.
    int areaLightBudget = 32;
    // With a Visibility: directions drawn from each environment light per pixel for its
    // shadows (0: none, the environment is unshadowed). 16, denoised, is clean
    // (docs/ibl.md, "Denoising").
    int environmentSamples = 16;
    // How environments' specular light is integrated (ibl.h): the split sum, a quadrature of
    // the exact lobe, or each where it is accurate (Auto).
    IblSpecular environmentSpecular = IblSpecular::Auto;
    // Ray-traced AO with a Visibility: cosine-weighted rays per pixel (0: no AO) ...
    int aoSamples = 0;
    // ... and the distance within which a hit occludes, scene units (metres), > 0 (+∞ allowed).
    float aoDistance = 1.0f;
    // With LightingInputs::scene: rays per shadow-catcher pixel that gather the light the
    // objects bounce onto it, counted in its alpha as Cycles' catcher counts it (0: the
    // catcher's direct light only).
    int catcherBounceSamples = 16;
    // The reference instead of the deferred shading (needs LightingInputs::scene): every
    // sample's light by unbiased path tracing (path_tracer.h) — pathSamples paths of at most
    // pathBounces bounces after the first hit (0: direct light only) — plus its emission.
    // Probes, AO, the denoiser and the prefiltered environment are not used; a shadow
    // catcher is shaded as the surface it is.
    bool pathTrace = false;
    int pathSamples = 16;
    int pathBounces = 8;
    // With LightingInputs::scene: rays per pixel that gather the lit scene in glossy and
    // metallic surfaces (specular_indirect.h; where the lobe reflects at least 10 % of uniform
    // light), denoised (0: none; their environment's specular light alone).
    int specularSamples = 8;
    // The diffuse layer of every surface: glTF's Lambert, or Blender's Burley (brdf.h).
    DiffuseModel diffuse = DiffuseModel::Lambert;
    // Filter the environments' shadow-ray estimates and ray-traced AO over neighbouring pixels
    // of the same surface before use (denoise.h; a deep G-buffer's samples layer by layer,
    // sample_layers.h): clean at a few samples, and
    // blurred across kDenoiseReach pixels at most. A strip of a frame then needs
    // kDenoiseReach rows of G-buffer above and below the rows shaded (roi) for the result to
    // be the whole frame's. false: the unbiased per-pixel estimates.
    bool denoise = true;
    // Write an "AO" channel after A (1 where AO is off).
    bool writeAO = false;
    // Also write the probes' indirect light as indirect.R, indirect.G, indirect.B (after AO).
    bool writeIndirect = false;
    // Also write the specular indirect light as specular.R, specular.G, specular.B (after
    // indirect), when it is traced.
    bool writeSpecular = false;
    // Set by another thread (the Python module's Ctrl-C) to stop the pass at its next row; the
    // call then fails with "cancelled" and its output is not to be used. Null: never.
    const std::atomic<bool>* cancel = nullptr;
};

// The ranges of LightingParams' counts, and the options of dhdr-light and keywords of
// dhdr.light() that set them.
inline constexpr IntParam<LightingParams> kLightingParamTable[] = {
    {"--shadow-samples", &LightingParams::shadowSamples, 1, 4096, "N",
     "points per pixel on each sphere, rectangle or emissive light, for soft shadows",
     "shadow_samples"},
    {"--light-budget", &LightingParams::areaLightBudget, 0, 65536, "N",
     "shadow rays per pixel shared by the area and emissive lights that reach it, chosen by "
     "their light, when --shadow-samples each would trace more (at least --shadow-samples; 0: "
     "every light its own --shadow-samples)",
     "light_budget"},
    {"--env-samples", &LightingParams::environmentSamples, 0, 4096, "N",
     "with --scene, shadow rays per pixel drawn from each environment light by its luminance, "
     "the cosine and the glossy lobe, so that the sky casts soft shadows (0: none)",
     "env_samples"},
    {"--catcher-bounce", &LightingParams::catcherBounceSamples, 0, 4096, "N",
     "with --scene, rays per shadow-catcher pixel that gather the light the objects bounce "
     "onto it, which lightens their shadow as in Cycles (0: direct light only)",
     "catcher_bounce"},
    {"--spp", &LightingParams::pathSamples, 1, 65536, "N",
     "--gi path: paths per pixel (per sample of a deep pixel)", "spp"},
    {"--path-bounces", &LightingParams::pathBounces, 0, 1024, "N",
     "--gi path: bounces after the first hit, ended earlier by Russian roulette (0: direct "
     "light only)",
     "path_bounces"},
    {"--specular-samples", &LightingParams::specularSamples, 0, 4096, "N",
     "with --scene, rays per pixel that gather the lit scene in metallic and glossy surfaces "
     "(the room in a gold sphere; 0: none)",
     "specular_samples"},
    {"--ao-samples", &LightingParams::aoSamples, 0, 4096, "N",
     "--ao rt: ambient-occlusion rays per pixel (0: no AO)", "ao_samples"},
    {"--tile", &LightingParams::tileSize, 1, 1024, "N", "tile size of the light lists, in pixels",
     "tile"},
};

// The rows around a strip of a frame that its environments' specular light reads (a flat
// pixel's mirror directions are compared with its neighbours' to filter the sky over its
// footprint; ibl.h, shadeIbl): a strip shaded with them gives the whole frame's pixels.
inline constexpr int kFootprintReach = 1;

// Whether `params` are within their ranges (kLightingParamTable, and the AO distance > 0);
// false with `error` naming the first that is not.
bool validate(const LightingParams& params, std::string& error);

} // namespace dhdr
