// The deferred lighting pass: a G-buffer and a list of lights in, linear HDR radiance out.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/deferred/ibl.h>
#include <dhdr/deferred/lights.h>
#include <dhdr/deferred/param_table.h>
#include <dhdr/deferred/visibility.h>
#include <memory>
#include <string>
#include <vector>

namespace dhdr {

struct DeepGBuffer;
struct ProbeVolume;
class RayCaster;

// The Monte Carlo estimates a strip traced (environment shadow sums, AO, a catcher's bounce light,
// the specular indirect light) in its last rows, before filtering, handed to the next strip of
// the same frame, which holds those rows as the halo above its own: they are not traced again.
// The same bits as tracing them again (every sequence depends only on the pixel); one carry per
// frame, passed to its strips in order (LightingInputs::carry). Opaque.
class EstimateCarry {
public:
    EstimateCarry();
    ~EstimateCarry();
    EstimateCarry(const EstimateCarry&) = delete;
    EstimateCarry& operator=(const EstimateCarry&) = delete;
    struct Rows; // filtered_estimates.cpp
    std::unique_ptr<Rows> rows;
};

// What lights the G-buffer, besides its own emission.
struct LightingInputs {
    const std::vector<Light>& lights;
    // The scene, for shadow and ambient-occlusion rays (a RayCaster); null: nothing blocks
    // light and AO is 1 unless `ambientOcclusion` gives it.
    const Visibility* visibility = nullptr;
    // Precomputed AO (one channel, e.g. screenSpaceAO) over the pixels shaded, in the same
    // pixel coordinates as the G-buffer; it takes precedence over ray-traced AO.
    const OIIO::ImageBuf* ambientOcclusion = nullptr;
    // A photograph (RGB, the frame's pixels) the result is composited over ("over": RGB +
    // plate × (1 − A), A = 1): objects and their caught shadows onto the real place.
    const OIIO::ImageBuf* plate = nullptr;
    // Light probes (probes.h): indirect diffuse light, diffuseAlbedo × E / π with E
    // interpolated from the probes around each point, times AO when AO is on. Environments'
    // diffuse light then comes through the probes; their specular light stays the IBL's.
    const ProbeVolume* probes = nullptr;
    // The scene's closest hits (usually the same RayCaster as `visibility`): a shadow catcher
    // then counts the light the objects bounce onto it (params.catcherBounceSamples).
    const RayCaster* scene = nullptr;
    // Optional, for strips of one frame shaded in order: the previous strip's estimates in the
    // rows both hold (read), this strip's for the next (written). Null: every row is traced.
    EstimateCarry* carry = nullptr;
};

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
    // of the same surface before use (denoise.h; flat G-buffers): clean at a few samples, and
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
};

// The ranges of LightingParams' counts, and the options of dhdr-light that set them.
inline constexpr IntParam<LightingParams> kLightingParamTable[] = {
    {"--shadow-samples", &LightingParams::shadowSamples, 1, 4096, "N",
     "points per pixel on each sphere, rectangle or emissive light, for soft shadows"},
    {"--env-samples", &LightingParams::environmentSamples, 0, 4096, "N",
     "with --scene, shadow rays per pixel drawn from each environment light by its luminance, "
     "the cosine and the glossy lobe, so that the sky casts soft shadows (0: none)"},
    {"--catcher-bounce", &LightingParams::catcherBounceSamples, 0, 4096, "N",
     "with --scene, rays per shadow-catcher pixel that gather the light the objects bounce "
     "onto it, which lightens their shadow as in Cycles (0: direct light only)"},
    {"--spp", &LightingParams::pathSamples, 1, 65536, "N",
     "--gi path: paths per pixel (per sample of a deep pixel)"},
    {"--path-bounces", &LightingParams::pathBounces, 0, 1024, "N",
     "--gi path: bounces after the first hit, ended earlier by Russian roulette (0: direct "
     "light only)"},
    {"--specular-samples", &LightingParams::specularSamples, 0, 4096, "N",
     "with --scene, rays per pixel that gather the lit scene in metallic and glossy surfaces "
     "(the room in a gold sphere; 0: none)"},
    {"--ao-samples", &LightingParams::aoSamples, 0, 4096, "N",
     "--ao rt: ambient-occlusion rays per pixel (0: no AO)"},
    {"--tile", &LightingParams::tileSize, 1, 1024, "N", "tile size of the light lists, in pixels"},
};

// The rows around a strip of a frame that its environments' specular light reads (a flat
// pixel's mirror directions are compared with its neighbours' to filter the sky over its
// footprint; ibl.h, shadeIbl): a strip shaded with them gives the whole frame's pixels.
inline constexpr int kFootprintReach = 1;

// Whether `params` are within their ranges (kLightingParamTable, and the AO distance > 0);
// false with `error` naming the first that is not.
bool validate(const LightingParams& params, std::string& error);

struct LightingStats {
    // Lights considered, summed over covered pixels: those in the pixel's tile list whose
    // depth slice matches (every light with bruteForce).
    long long lightEvaluations = 0;
    // Of those, the lights whose range actually reaches the pixel's surface point.
    long long lightsReaching = 0;
    long long coveredPixels = 0;
    // Entries of all the tile lists.
    long long tileListEntries = 0;
    long long shadowRays = 0, aoRays = 0;
    // Rays of a shadow catcher's bounce light: to the objects, and their shadow rays.
    long long bounceRays = 0;
    // Rays of the reference path tracer (--gi path): its paths' and their shadow rays.
    long long pathRays = 0;
    // Rays of the specular indirect light, and their hits' shadow rays.
    long long specularRays = 0;

    LightingStats& operator+=(const LightingStats& o);
};

// Shades every covered pixel of `roi` of `gbuffer` (undefined: all of it) and writes R, G, B,
// A (then AO with writeAO, then `passThrough`) as float pixels into `dst`, whose spec keeps
// `gbuffer`'s metadata. For each surface point (shading_point.h):
//   Lo = emission + Σ_lights V_i · L_i + AO · Σ_ambient L_a
// with L_i the light's exact unshadowed reflection (Lambert + Cook-Torrance, brdf.h; area
// lights lights/area.h; environments the split sum of ibl.h), V_i its visibility (shadows.h; 1
// without a Visibility) and AO the ambient occlusion (ambient_occlusion.h). AO multiplies only
// the ambient terms (ambient lights, environments' diffuse light; their specular light by
// specular occlusion): punctual and area lights have their shadows. Pixels of the G-buffer's
// shadow catcher (gbuffer::kShadowCatcher) get RGB 0 and A = 1 − shadowed / unshadowed
// luminance; with a plate, every pixel is then composited over it. Each light is evaluated only at
// the pixels of the tiles and depth slices its bound reaches (light_culling.h), in the order of the
// lights, so culled and brute-force results agree to rounding; every sample sequence depends only
// on the pixel and the light, so results do not depend on `nthreads` or on the strip. Errors (a
// missing channel, no camera in the header) are reported on `dst`. `dst` is reused when it already
// holds float pixels of the right size and channels (the previous strip).
bool shadeGBuffer(OIIO::ImageBuf& dst, const OIIO::ImageBuf& gbuffer, const LightingInputs& inputs,
                  const LightingParams& params = {}, OIIO::ROI roi = {}, int nthreads = 0,
                  LightingStats* stats = nullptr);

// A deep G-buffer (deep_gbuffer.h), its whole frame or a band of its rows (params.frame, as for
// flat strips; the same pixels either way): every sample is lit as an opaque surface
// would be (the same tile lists, bounded by all samples' depths; shadow and AO rays from each;
// its own sample sequences, sample 0's those of a flat pixel) and the samples are composited
// front to back, premultiplied "over", into the flat RGBA of `dst`; what is left uncovered
// shows the background (params.background or the environment) and the plate. With
// `sampleRGBA`, each sample's own premultiplied RGBA (4 floats a sample, in the order of
// gbuffer.values) for a deep output. An AO image (one value a pixel) is an error here.
bool shadeGBuffer(OIIO::ImageBuf& dst, const DeepGBuffer& gbuffer, const LightingInputs& inputs,
                  const LightingParams& params = {}, OIIO::ROI roi = {}, int nthreads = 0,
                  LightingStats* stats = nullptr, std::vector<float>* sampleRGBA = nullptr);

} // namespace dhdr
