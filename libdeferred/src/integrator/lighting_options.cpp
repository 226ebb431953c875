#include <algorithm>
#include <dhdr/deferred/integrator/lighting_options.h>

namespace dhdr {

namespace {

// How a message names what the user gave: an option and its value as typed on the command
// line ("--gi path", "give --scene SCENE") or as a keyword of dhdr.light() ("gi='path'",
// "give scene=").
struct Words {
    Spelling spelling;

    std::string name(const char* option, const char* keyword) const {
        return spelling == Spelling::Keyword ? keyword : option;
    }
    std::string set(const char* option, const char* keyword, const char* value) const {
        return spelling == Spelling::Keyword ? std::string(keyword) + "='" + value + "'"
                                             : std::string(option) + " " + value;
    }
    std::string giveScene() const {
        return spelling == Spelling::Keyword ? "give scene=" : "give --scene SCENE";
    }
};

// The rules between the choices, first broken first; empty when none is.
std::string ruleBroken(const LightingOptions& o, const LightingContext& c, const Words& w) {
    const LightingParams& p = o.params;
    const LightingParams defaults = LightingOptions{}.params;
    if (!c.lights && !c.scene)
        return w.spelling == Spelling::Keyword
                   ? "no lights: give lights=, or scene= for the scene's own"
                   : "no lights: give --lights FILE, or --scene SCENE for the scene's own";
    const std::string path = w.set("--gi", "gi", "path");
    if (!p.pathTrace &&
        (p.pathSamples != defaults.pathSamples || p.pathBounces != defaults.pathBounces))
        return w.name("--spp", "spp") + " and " + w.name("--path-bounces", "path_bounces") +
               " are for " + path;
    if (p.pathTrace) {
        if (!c.scene) return path + " traces the scene: " + w.giveScene();
        if (c.probes)
            return path + " computes the indirect light itself: drop " +
                   w.name("--probes", "probes");
        if (o.ao != AoMode::Off) return path + " has no AO: drop " + w.name("--ao", "ao");
    }
    if (c.scene) return {};
    // Without a scene nothing is traced: an option that asks for rays is a mistake.
    if (o.ao == AoMode::RayTraced)
        return w.set("--ao", "ao", "rt") + " traces rays in the scene: " + w.giveScene();
    if (!p.shadows)
        return w.name("--no-shadows", "shadows=False") +
               " needs a scene (without it nothing is shadowed): " + w.giveScene();
    const struct {
        int LightingParams::*field;
        const char *option, *keyword;
    } traced[] = {
        {&LightingParams::environmentSamples, "--env-samples", "env_samples"},
        {&LightingParams::catcherBounceSamples, "--catcher-bounce", "catcher_bounce"},
        {&LightingParams::specularSamples, "--specular-samples", "specular_samples"},
    };
    for (const auto& t : traced)
        if (p.*(t.field) != defaults.*(t.field))
            return w.name(t.option, t.keyword) + " traces rays in the scene: " + w.giveScene();
    return {};
}

} // namespace

bool resolveLighting(const LightingOptions& options, const LightingContext& context,
                     Spelling spelling, LightingParams& params, SsaoParams& ssao,
                     std::string& error) {
    const Words words{spelling};
    error = checkRanges(options.params, kLightingParamTable, spelling);
    if (error.empty()) error = checkRanges(options, kLightingFloatTable, spelling);
    if (error.empty()) error = ruleBroken(options, context, words);
    if (!error.empty()) return false;
    params = options.params;
    if (params.pathTrace) params.denoise = false; // the reference is each pixel's own estimate
    params.aoSamples = options.ao == AoMode::RayTraced ? options.params.aoSamples : 0;
    params.aoDistance = options.aoDistance;
    params.environmentBackground = options.environmentBackground;
    params.plateEnvironment = options.plateEnvironment;
    if (options.aovs) params.passThrough = {"Z", "N.X", "N.Y", "N.Z"};
    params.writeAO = options.aovs && options.ao != AoMode::Off;
    params.writeIndirect = options.aovs && context.probes;
    params.writeSpecular = options.aovs && context.scene;
    ssao.samples = options.params.aoSamples;
    ssao.radius = options.aoDistance;
    if (options.ao == AoMode::ScreenSpace)
        if (error = checkRanges(ssao, kSsaoParamTable, spelling); !error.empty()) {
            error += " with " + words.set("--ao", "ao", "ssao");
            return false;
        }
    return true;
}

ProbePlan planProbes(const LightingOptions& options, const LightingContext& context,
                     const std::vector<Light>& lights, bool catcher, Spelling spelling) {
    if (context.probes) return {ProbeSource::Given, {}};
    if (options.gi != GiMode::Auto || !context.scene) return {};
    const Words w{spelling};
    const std::string give = w.spelling == Spelling::Keyword
                                 ? "bake them with dhdr.bake_probes() and give probes="
                                 : "bake them with dhdr-probes and give --probes FILE";
    const bool environment = std::any_of(lights.begin(), lights.end(), isEnvironment);
    if (environment || catcher)
        return {ProbeSource::None,
                w.set("--gi", "gi", "auto") + ": no probes baked " +
                    (environment ? "under an environment light" : "over a shadow catcher") +
                    " (in the open they move the catcher's shadows by up to 100 %): the light "
                    "the objects bounce between themselves is left out; " +
                    give + " to add it anyway"};
    return {ProbeSource::Bake,
            w.set("--gi", "gi", "auto") +
                ": indirect light from probes baked for this frame (dhdr-probes' defaults; " +
                w.set("--gi", "gi", "direct") + " leaves it out, " + w.name("--probes", "probes=") +
                " reuses a bake)"};
}

std::string deepGBufferProblem(const LightingOptions& options, Spelling spelling) {
    if (options.ao != AoMode::ScreenSpace) return {};
    const Words w{spelling};
    return w.set("--ao", "ao", "ssao") + " works on flat G-buffers; a deep one needs " +
           w.set("--ao", "ao", "rt");
}

} // namespace dhdr
