// The user's lighting choices, as dhdr-light's options and dhdr.light()'s keywords give them,
// and the rules between them, resolved once into the lighting pass's parameters: the tool and
// the Python module both fill a LightingOptions from these tables and call resolveLighting,
// so that a rule, its message, a choice's names and a default exist once.
#pragma once

#include <dhdr/common/param_table.h>
#include <dhdr/deferred/direct/ambient_occlusion.h>
#include <dhdr/deferred/integrator/lighting_params.h>
#include <dhdr/deferred/scene/lights.h>
#include <string>
#include <vector>

namespace dhdr {

enum class AoMode { Off, RayTraced, ScreenSpace }; // off | rt | ssao
enum class GiMode { Auto, Direct, Path };          // auto | direct | path

struct LightingOptions {
    // The counts (kLightingParamTable), tile size, brute force, shadows, denoise, diffuse
    // model and environment specular as the pass takes them; resolveLighting sets the rest.
    LightingParams params = withAoSamples(16);
    AoMode ao = AoMode::Off; //!< --ao: rt traces rays (params.aoSamples), ssao a kernel
    float aoDistance = 1.0f; //!< --ao-distance, scene units (metres), (0, 1e30]
    bool aovs = false;       //!< --aovs: AO, indirect and specular AOVs, Z and N passed through
    bool environmentBackground = false; //!< --background env
    bool plateEnvironment = false;      //!< --plate env
    //! --gi: auto adds the indirect light of probes baked for the frame (planProbes); path
    //! sets params.pathTrace.
    GiMode gi = GiMode::Auto;

private:
    static LightingParams withAoSamples(int n) {
        LightingParams p;
        p.aoSamples = n; // rays with --ao rt, kernel points with ssao; unused when AO is off
        return p;
    }
};

// What the choices are resolved against: what the call was given.
struct LightingContext {
    bool lights = false; // lights files or lights given
    bool scene = false;  // a scene to trace
    bool probes = false; // light probes
};

inline constexpr FloatParam<LightingOptions> kLightingFloatTable[] = {
    {"--ao-distance",
     "ao_distance",
     &LightingOptions::aoDistance,
     {0.0, 1e30, true, false},
     "D",
     "rt: a hit closer than D occludes; ssao: the kernel's radius; scene units, metres for glTF"},
};

inline constexpr ChoiceParam<LightingOptions> kLightingChoiceTable[] = {
    {"--ao", "ao", "off|rt|ssao", [](const LightingOptions& o) { return int(o.ao); },
     [](LightingOptions& o, int i) { o.ao = AoMode(i); },
     "ambient occlusion of the ambient light: rt traces rays in the scene (needs --scene), ssao "
     "works from the G-buffer alone"},
    {"--env-specular", "env_specular", "auto|split-sum|quadrature",
     [](const LightingOptions& o) { return int(o.params.environmentSpecular); },
     [](LightingOptions& o, int i) { o.params.environmentSpecular = IblSpecular(i); },
     "how environments' specular light is integrated: the split sum (prefiltered "
     "levels), a 32-sample quadrature of the exact lobe (right at grazing angles on "
     "rough surfaces, where the split sum is 10-15 % dark), or auto: the quadrature "
     "from roughness 0.3 up (docs/ibl.md)"},
    {"--denoise", "denoise", "on|off",
     [](const LightingOptions& o) { return o.params.denoise ? 0 : 1; },
     [](LightingOptions& o, int i) { o.params.denoise = i == 0; },
     "filter the environments' shadow rays (--env-samples) and --ao rt over "
     "neighbouring pixels of the same surface, guided by the G-buffer's normals, "
     "positions and object ids (edge-avoiding a-trous, 32 pixels' reach; deep "
     "G-buffers layer by layer); off: each pixel's unbiased estimate"},
    {"--gi", "gi", "auto|direct|path", [](const LightingOptions& o) { return int(o.gi); },
     [](LightingOptions& o, int i) {
         o.gi = GiMode(i);
         o.params.pathTrace = o.gi == GiMode::Path;
     },
     "auto: deferred shading plus indirect light from light probes, --probes' or, with --scene "
     "and no environment light or shadow catcher, probes baked for the frame as dhdr-probes "
     "bakes them by default (a few seconds); direct: deferred shading, indirect light only "
     "from --probes; path: the reference, unbiased path tracing from each pixel's first hit "
     "(needs --scene; --spp paths a pixel, --path-bounces; no denoiser, probes or AO; slow: "
     "use it on a small frame or a crop to check a fast render; docs/gi.md)"},
};

inline constexpr FlagParam<LightingOptions> kLightingFlagTable[] = {
    {"--no-shadows", "shadows", [](const LightingOptions& o) { return o.params.shadows; },
     [](LightingOptions& o, bool v) { o.params.shadows = v; }, true,
     "with --scene, trace no shadow rays (the unshadowed reference; AO is still traced)"},
    {"--brute-force", "brute_force", [](const LightingOptions& o) { return o.params.bruteForce; },
     [](LightingOptions& o, bool v) { o.params.bruteForce = v; }, false,
     "evaluate every light at every pixel (the reference)"},
    {"--aovs", "aovs", [](const LightingOptions& o) { return o.aovs; },
     [](LightingOptions& o, bool v) { o.aovs = v; }, false,
     "also write the G-buffer's Z and N.X N.Y N.Z channels (and its motion layer, motion.X-W, "
     "when it has one), AO, the probes' indirect.R/G/B and the specular indirect light "
     "specular.R/G/B"},
};

// `options` as the pass's parameters and, with AoMode::ScreenSpace, the SSAO kernel's: the
// ranges of every table checked, then the rules between the choices (the path tracer needs a
// scene and takes no probes or AO, --spp only with it, rays need a scene, …). False with
// `error`, spelled as the caller's user wrote the choices (options or keywords).
bool resolveLighting(const LightingOptions& options, const LightingContext& context,
                     Spelling spelling, LightingParams& params, SsaoParams& ssao,
                     std::string& error);

// Where a frame's indirect diffuse light comes from (--gi auto).
enum class ProbeSource {
    None,  // direct light only (--gi direct or path, no scene, or auto where probes fail)
    Given, // the probes the caller gave (--probes)
    Bake   // probes baked for the frame with ProbeBakeParams' defaults, as dhdr-probes does
};
struct ProbePlan {
    ProbeSource source = ProbeSource::None;
    // Why auto bakes none, or what it bakes, for the caller to say; empty when nothing is.
    std::string note;
};

// The probes of a frame lit by `lights` (the scene's and the files'), `catcher` when its
// scene has a shadow-catching ground plane. --gi auto bakes none under an environment light
// or over a catcher: probes in the open darken the catcher's shadows and frost the objects'
// faces (docs/gi.md, "Probes by default").
ProbePlan planProbes(const LightingOptions& options, const LightingContext& context,
                     const std::vector<Light>& lights, bool catcher, Spelling spelling);

// What stops `options` on a deep G-buffer (SSAO reads a flat one's neighbours); empty when
// nothing does.
std::string deepGBufferProblem(const LightingOptions& options, Spelling spelling);

} // namespace dhdr
