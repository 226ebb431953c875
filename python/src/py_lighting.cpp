// The lighting stage (libdeferred): light() and light_samples() on flat and deep G-buffers with
// dhdr-light's options, lights from files or Python objects (the readers: py_gbuffer_input.cpp).
#include "py_deep.h"
#include "py_interrupt.h"
#include "py_lights.h"
#include "py_ops.h"
#include "py_probes.h"
#include "py_scene.h"

#include <algorithm>
#include <cmath>
#include <dhdr/deferred/direct/ambient_occlusion.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_time.h>
#include <dhdr/deferred/geometry/posed_scene.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/integrator/lighting_options.h>
#include <dhdr/deferred/lights/emissive_lights.h>
#include <dhdr/deferred/scene/lights.h>
#include <filesystem>
#include <memory>
#include <optional>
#include <pybind11/stl.h>
#include <stdexcept>
#include <tuple>

namespace dhdr::python {

namespace {

using namespace pybind11::literals;

// The scene as dhdr-light --scene lights a G-buffer (its PosedScene): posed at the moment the
// G-buffer's header records (gbuffer_time.h) with the animations it records, on a copy with its
// own ray caster; as loaded (caster null: the dhdr.Scene's own) when the G-buffer records no
// moment or the file has no animations.
struct PosedFor {
    std::shared_ptr<const Scene> scene;
    std::shared_ptr<const RayCaster> caster;
};

PosedFor poseFor(const SceneHandle& h, const OIIO::ImageSpec& gspec) {
    std::optional<gbuffer::Moment> moment;
    if (std::string error; !gbuffer::readMoment(gspec, moment, error))
        throw py::value_error("gbuffer: " + error);
    std::vector<int> playing;
    PoseReport report;
    const bool chosen = animationsAtMoment(*h.scene, h.path, "gbuffer", moment, playing, report);
    for (const std::string& w : report.warnings)
        python::warn(w);
    if (!chosen && report.fault == PoseFault::GBuffer) throw py::value_error(report.error);
    if (!chosen) raiseError(report.error);
    if (playing.empty()) return {h.scene, nullptr};
    auto posed = std::make_shared<PosedScene>();
    std::string error;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        posed->hold(h.scene, h.path);
        posed->play(playing);
        ok = posed->pose(moment->time, error);
    }
    if (!ok) raiseError(h.path + ": " + error);
    return {std::shared_ptr<const Scene>(posed, &posed->scene()),
            std::shared_ptr<const RayCaster>(posed, posed->caster().get())};
}

// light()'s keywords after its G-buffer, in the order declared (lightKeywords): what a call
// gives, before anything is checked.
struct LightCall {
    py::object lights, scene;
    bool emissive, shadows;
    int envSamples, specularSamples, catcherBounce;
    py::object probes;
    std::string ao;
    float aoDistance;
    int aoSamples;
    py::object background, plate;
    bool bruteForce;
    int tile, shadowSamples, lightBudget;
    std::string envSpecular, diffuse;
    bool radiometric, denoise, aovs;
    std::string gi;
    int spp, pathBounces;

    // The lighting choices, as dhdr-light's options give them (LightingOptions' tables).
    LightingOptions options() const;
};

// The keywords of light() (flat and deep) and light_samples(), declared once, their defaults
// those of LightingOptions and its tables.
auto lightKeywords() {
    const LightingOptions d;
    const auto choice = [&d](const char* option) {
        for (const ChoiceParam<LightingOptions>& p : kLightingChoiceTable)
            if (std::string(p.option) == option) return choiceName(p.names, p.get(d));
        throw std::logic_error(std::string("no choice ") + option);
    };
    return std::make_tuple(
        py::arg("lights") = py::none(), py::kw_only(), py::arg("scene") = py::none(),
        py::arg("emissive_lights") = true, py::arg("shadows") = d.params.shadows,
        py::arg("env_samples") = d.params.environmentSamples,
        py::arg("specular_samples") = d.params.specularSamples,
        py::arg("catcher_bounce") = d.params.catcherBounceSamples, py::arg("probes") = "",
        py::arg("ao") = choice("--ao"), py::arg("ao_distance") = d.aoDistance,
        py::arg("ao_samples") = d.params.aoSamples, py::arg("background") = py::none(),
        py::arg("plate") = py::none(), py::arg("brute_force") = d.params.bruteForce,
        py::arg("tile") = d.params.tileSize, py::arg("shadow_samples") = d.params.shadowSamples,
        py::arg("light_budget") = d.params.areaLightBudget,
        py::arg("env_specular") = choice("--env-specular"), py::arg("diffuse") = "lambert",
        py::arg("radiometric") = false, py::arg("denoise") = d.params.denoise,
        py::arg("aovs") = d.aovs, py::arg("gi") = choice("--gi"),
        py::arg("spp") = d.params.pathSamples, py::arg("path_bounces") = d.params.pathBounces);
}

LightingOptions LightCall::options() const {
    LightingOptions o;
    std::string error;
    const struct {
        const char* option;
        std::string value;
    } choices[] = {{"--ao", ao}, {"--env-specular", envSpecular}, {"--gi", gi}};
    for (const auto& c : choices)
        for (const ChoiceParam<LightingOptions>& p : kLightingChoiceTable)
            if (std::string(p.option) == c.option &&
                !setChoice(p, o, c.value, Spelling::Keyword, error))
                throw py::value_error(error);
    if (diffuse != "lambert" && diffuse != "burley")
        throw py::value_error("diffuse must be lambert or burley");
    o.params.diffuse = diffuse == "burley" ? DiffuseModel::Burley : DiffuseModel::Lambert;
    o.params.bruteForce = bruteForce;
    o.params.tileSize = tile;
    o.params.shadowSamples = shadowSamples;
    o.params.areaLightBudget = lightBudget;
    o.params.denoise = denoise;
    o.params.shadows = shadows;
    o.params.environmentSamples = envSamples;
    o.params.specularSamples = specularSamples;
    o.params.catcherBounceSamples = catcherBounce;
    o.params.aoSamples = aoSamples;
    o.params.pathSamples = spp;
    o.params.pathBounces = pathBounces;
    o.aoDistance = aoDistance;
    o.aovs = aovs;
    return o;
}

// What light() needs for a call, prepared from its keywords with the GIL held (ValueError for
// bad ones), shared by the flat and the deep forms.
struct LightingSetup {
    std::shared_ptr<std::vector<Light>> lights;
    LightingParams p;
    SsaoParams ssao;
    std::shared_ptr<const ProbeVolume> probes;
    std::shared_ptr<ImageView> plateImage;
    PosedFor posed; // keeps the posed scene and its caster alive
    const RayCaster* caster = nullptr;
    bool useSsao = false, useProbes = false;
};

// The background and plate keywords into `o` (and the plate's image).
void readBackdrops(const LightCall& c, LightingOptions& o, ImageView& plateImage) {
    if (py::isinstance<py::str>(c.background)) {
        if (c.background.cast<std::string>() != "env")
            throw py::value_error("background must be (R, G, B[, A]) or 'env'");
        o.environmentBackground = true;
    } else if (!c.background.is_none()) {
        const std::vector<double> v = c.background.cast<std::vector<double>>();
        if (v.size() != 3 && v.size() != 4)
            throw py::value_error("background needs 3 or 4 numbers");
        // As dhdr-light's --background: NaN, ±Inf and what a float cannot hold are refused.
        for (const double x : v)
            if (!std::isfinite(float(x)))
                throw py::value_error("background: " + py::repr(py::float_(x)).cast<std::string>() +
                                      " is not a finite number a float holds");
        for (size_t i = 0; i < 4; ++i)
            o.params.background[i] = i < v.size() ? float(v[i]) : 1.0f;
    }
    if (py::isinstance<py::str>(c.plate)) {
        if (c.plate.cast<std::string>() != "env")
            throw py::value_error("plate must be an image or 'env'");
        o.plateEnvironment = true;
    } else if (!c.plate.is_none()) {
        Image storage;
        plateImage = view(asImage(c.plate, "plate", storage));
    }
}

// gi='auto': the probes dhdr-light bakes for a frame (planProbes), with dhdr.bake_probes()'s
// defaults; Ctrl-C stops the bake and raises KeyboardInterrupt.
std::shared_ptr<const ProbeVolume> bakeFrameProbes(const Scene& scene, const RayCaster& caster,
                                                   const std::vector<Light>& lights, bool emissive,
                                                   DiffuseModel diffuse) {
    auto volume = std::make_shared<ProbeVolume>();
    ProbeBakeParams p;
    p.diffuse = diffuse;
    std::atomic<bool> cancel{false};
    p.cancel = &cancel;
    std::string error;
    bool ok = false;
    runInterruptibly(cancel,
                     [&] { ok = bakeProbes(scene, caster, lights, emissive, p, *volume, error); });
    // The frame's direct light does not depend on them: it is still made, without them.
    if (!ok) {
        python::warn("gi='auto': the probes cannot be baked (" + error +
                     "); the frame is lit without indirect light, as with gi='direct'");
        return nullptr;
    }
    roundAsStored(*volume);
    return volume;
}

LightingSetup setupLighting(const OIIO::ImageSpec& gspec, const LightCall& c) {
    // probes: a file's path or a dhdr.Probes; "" and None are none.
    const bool hasProbes = !c.probes.is_none() && !(py::isinstance<py::str>(c.probes) &&
                                                    c.probes.cast<std::string>().empty());
    const SceneHandle* scene = nullptr;
    if (!c.scene.is_none()) {
        if (!py::isinstance<SceneHandle>(c.scene))
            throw py::type_error("scene: expected a dhdr.Scene");
        scene = &c.scene.cast<const SceneHandle&>();
    }
    LightingOptions options = c.options();
    auto plateImage = std::make_shared<ImageView>();
    readBackdrops(c, options, *plateImage);
    LightingSetup s{nullptr, {}, {}, nullptr, plateImage, {}, nullptr, false, false};
    const LightingContext context{!c.lights.is_none(), scene != nullptr, hasProbes};
    if (std::string error;
        !resolveLighting(options, context, Spelling::Keyword, s.p, s.ssao, error))
        throw py::value_error(error);
    // dhdr-light's lights: the scene's own unless lights are given, its emissive meshes, then
    // the lights given (sceneLightList's order), where the G-buffer's moment puts them.
    s.posed = scene ? poseFor(*scene, gspec) : PosedFor{};
    s.lights = std::make_shared<std::vector<Light>>(
        scene ? sceneLightList(*s.posed.scene, c.lights.is_none(), c.emissive, c.radiometric)
              : std::vector<Light>{});
    if (scene && c.lights.is_none() && s.lights->empty())
        throw py::value_error(scene->path + ": the scene has no lights and no emissive "
                                            "surfaces; give lights=");
    if (!c.lights.is_none()) {
        const std::vector<Light> given = lightsOf(c.lights, c.radiometric);
        s.lights->insert(s.lights->end(), given.begin(), given.end());
    }
    if (options.plateEnvironment && std::none_of(s.lights->begin(), s.lights->end(), isEnvironment))
        throw py::value_error("plate='env': there is no environment light to composite over");
    s.probes = probesOf(c.probes);
    s.useSsao = options.ao == AoMode::ScreenSpace;
    // The scene's rays (shadows, AO, a catcher's bounce light, glossy reflections); the
    // caller's dhdr.Scene keeps them alive for the call.
    s.caster = s.posed.caster ? s.posed.caster.get() : scene ? &scene->caster() : nullptr;
    const bool catcher = scene && s.posed.scene->hasGroundPlane;
    if (planProbes(options, context, *s.lights, catcher, Spelling::Keyword).source ==
        ProbeSource::Bake)
        s.probes = bakeFrameProbes(*s.posed.scene, *s.caster, *s.lights, c.emissive, s.p.diffuse);
    s.useProbes = bool(s.probes);
    if (s.useProbes) s.p.writeIndirect = options.aovs;
    return s;
}

// The plate, when there is one, laid on the frame's pixels; false with the message on `dst`.
bool placePlate(const LightingSetup& s, const OIIO::ImageSpec& gs, OIIO::ImageBuf& dst,
                LightingInputs& inputs) {
    if (!s.plateImage->buf.initialized()) return true;
    const OIIO::ImageSpec& ps = s.plateImage->buf.spec();
    if (ps.width != gs.width || ps.height != gs.height) {
        dst.errorfmt("the plate is {}x{}, the frame {}x{}", ps.width, ps.height, gs.width,
                     gs.height);
        return false;
    }
    s.plateImage->buf.set_origin(gs.x, gs.y);
    inputs.plate = &s.plateImage->buf;
    return true;
}

LongOp lightOp(const Image& src, const LightCall& call) {
    auto s = std::make_shared<const LightingSetup>(setupLighting(src.spec(), call));
    return {[s](OIIO::ImageBuf& dst, const OIIO::ImageBuf& gbuf, OIIO::ROI roi, int n,
                const std::atomic<bool>& cancel) {
        LightingInputs inputs{*s->lights, s->caster};
        inputs.scene = s->caster;
        OIIO::ImageBuf occlusion;
        if (s->useSsao) {
            if (!screenSpaceAO(occlusion, gbuf, s->ssao, n)) {
                dst.errorfmt("{}", occlusion.geterror());
                return false;
            }
            inputs.ambientOcclusion = &occlusion;
        }
        if (s->useProbes) inputs.probes = s->probes.get();
        if (!placePlate(*s, gbuf.spec(), dst, inputs)) return false;
        LightingParams p = s->p;
        p.cancel = &cancel;
        return shadeGBuffer(dst, gbuf, inputs, p, roi, n);
    }};
}

// dhdr-light on a deep G-buffer: every sample lit and composited front to back into flat RGBA,
// the tile lists laid over the whole frame (what the tool's bands share).
LongOp deepLightOp(const DeepHandle& src, const LightCall& call) {
    if (const std::string problem = deepGBufferProblem(call.options(), Spelling::Keyword);
        !problem.empty())
        throw py::value_error(problem);
    auto s = std::make_shared<const LightingSetup>(setupLighting(src.g->spec, call));
    const std::shared_ptr<const DeepGBuffer> g = src.g;
    return {[s, g](OIIO::ImageBuf& dst, const OIIO::ImageBuf&, OIIO::ROI roi, int n,
                   const std::atomic<bool>& cancel) {
        LightingInputs inputs{*s->lights, s->caster};
        inputs.scene = s->caster;
        if (s->useProbes) inputs.probes = s->probes.get();
        if (!placePlate(*s, g->spec, dst, inputs)) return false;
        LightingParams p = s->p;
        p.frame = OIIO::get_roi(g->spec);
        p.cancel = &cancel;
        return shadeGBuffer(dst, *g, inputs, p, roi, n);
    }};
}

// dhdr-light --deep-out: each sample of a deep G-buffer lit, premultiplied, with its Z and
// ZBack, in the G-buffer's order (what the tool writes as a deep RGBA EXR for deep compositing).
DeepHandle lightSamples(const DeepHandle& src, const LightCall& call, int nthreads) {
    if (const std::string problem = deepGBufferProblem(call.options(), Spelling::Keyword);
        !problem.empty())
        throw py::value_error(problem);
    const LightingSetup s = setupLighting(src.g->spec, call);
    const std::shared_ptr<const DeepGBuffer> g = src.g;
    DeepHandle out;
    std::string error;
    std::atomic<bool> cancel{false};
    runInterruptibly(cancel, [&] {
        LightingInputs inputs{*s.lights, s.caster};
        inputs.scene = s.caster;
        if (s.useProbes) inputs.probes = s.probes.get();
        LightingParams p = s.p;
        p.frame = OIIO::get_roi(g->spec);
        p.cancel = &cancel;
        OIIO::ImageBuf flat;
        std::vector<float> rgba;
        if (!placePlate(s, g->spec, flat, inputs) ||
            !shadeGBuffer(flat, *g, inputs, p, {}, nthreads, nullptr, &rgba)) {
            error = flat.geterror();
        } else {
            DeepGBuffer& lit = *out.g;
            const size_t nch = size_t(g->spec.nchannels), n = g->totalSamples();
            lit.spec = g->spec;
            lit.spec.nchannels = 6;
            lit.spec.channelnames = {"R", "G", "B", "A", "Z", "ZBack"};
            lit.spec.alpha_channel = 3;
            lit.spec.z_channel = 4;
            lit.first = g->first;
            lit.values.resize(n * 6);
            for (size_t k = 0; k < n; ++k) {
                for (size_t c = 0; c < 4; ++c)
                    lit.values[6 * k + c] = rgba[4 * k + c];
                lit.values[6 * k + 4] = g->values[k * nch + 1]; // Z
                lit.values[6 * k + 5] = g->values[k * nch + 2]; // ZBack
            }
        }
    });
    if (!error.empty()) raiseError(error);
    return out;
}

// The C++ signatures of light()'s forms: the keywords' types in LightCall's order, each call
// gathered into a LightCall.
template <class... Keyword>
struct LightForms {
    static LongOp flat(const Image& src, Keyword... k) { return lightOp(src, LightCall{k...}); }
    static LongOp deep(const DeepHandle& src, Keyword... k) {
        return deepLightOp(src, LightCall{k...});
    }
    static DeepHandle samples(const DeepHandle& src, Keyword... k, int nthreads) {
        return lightSamples(src, LightCall{k...}, nthreads);
    }
};
using LightSignature =
    LightForms<const py::object&, const py::object&, bool, bool, int, int, int, const py::object&,
               const std::string&, float, int, const py::object&, const py::object&, bool, int, int,
               int, const std::string&, const std::string&, bool, bool, bool, const std::string&,
               int, int>;

// light()'s two forms with a DeepGBuffer as src, registered before the flat ones (whose src
// takes any object): the result is flat, so they run through runNew and runInto with a
// placeholder src that the operation does not read.
template <class... Args, class... Extra>
void defDeepOp(py::module_& m, const char* name, const char* doc,
               LongOp (*prepare)(const DeepHandle&, Args...), const Extra&... extra) {
    auto placeholder = [] {
        return Image(py::array_t<float>(std::vector<py::ssize_t>{1, 1, 1}), {}, "src");
    };
    m.def(
        name,
        [prepare, placeholder](const DeepHandle& src, Args... args, const py::object& roi,
                               int nthreads) {
            const LongOp op = prepare(src, args...);
            return runNew(placeholder(), toRoi(roi), nthreads, op);
        },
        py::arg("src"), extra..., py::arg("roi") = py::none(), py::arg("nthreads") = 0, doc);
    m.def(
        name,
        [prepare, placeholder](Image& dst, const DeepHandle& src, Args... args,
                               const py::object& roi, int nthreads) {
            const LongOp op = prepare(src, args...);
            return runInto(dst, placeholder(), toRoi(roi), nthreads, op);
        },
        py::arg("dst"), py::arg("src"), extra..., py::arg("roi") = py::none(),
        py::arg("nthreads") = 0, doc);
}

} // namespace

void bindLighting(py::module_& m) {
    std::apply(
        [&m](const auto&... keywords) {
            defDeepOp(
                m, "light",
                "A DeepGBuffer (dhdr-gbuffer --deep, read_gbuffer of a deep file): every sample "
                "lit as dhdr-light lights a deep G-buffer (shadow and AO rays from each; ao='rt', "
                "not 'ssao') and composited front to back into flat R, G, B, A. The keywords are "
                "those below.",
                &LightSignature::deep, keywords...);
            defImageOp(m, "light",
                       R"(Deferred lighting of a flat G-buffer (dhdr-light): Lambert (or Burley)
diffuse plus Cook-Torrance specular under the lights, plus emission; R, G, B, A (then AO,
indirect.R/G/B and Z, N.X, N.Y, N.Z with aovs). lights: a lights file (docs/lights.md), a
light as a dict of that file's fields, or a list of them, in order; radiometric divides
Blender's photometric intensities by 683. scene: the dhdr.Scene the G-buffer was rendered
from (--scene): shadow rays (shadows=False: none), its emissive meshes as area lights
(emissive_lights), its own lights when lights is None, all posed where the G-buffer's
header says it was rendered (dhdr:animationTime, as dhdr-light does); env_samples,
specular_samples and catcher_bounce trace it. probes: a dhdr-probes file or a dhdr.Probes
(indirect diffuse). ao: 'off', 'rt' (ao_samples rays within ao_distance; needs scene) or
'ssao' (from the G-buffer, ao_samples kernel points within ao_distance).
background: (R, G, B[, A]) or 'env'; plate: an image of the frame's size to composite over,
or 'env'. shadow_samples, light_budget, tile, env_specular ('auto', 'split-sum', 'quadrature'), denoise,
diffuse ('lambert', 'burley') and brute_force are dhdr-light's options of those names.
gi='auto' (the default), with scene and no probes: light probes baked for the frame as
dhdr-light bakes them (none under an environment light or over a shadow catcher);
gi='direct' leaves them out; gi='path' (with scene): the reference path tracer instead, spp
paths of at most path_bounces bounces a pixel, undenoised.
Without a scene nothing is shadowed, as dhdr-light without --scene.)",
                       &LightSignature::flat, keywords...);
            m.def(
                "light_samples", &LightSignature::samples, "src"_a, keywords...,
                py::arg("nthreads") = 0,
                R"(dhdr-light --deep-out: every sample of a DeepGBuffer lit as light() lights it, kept
apart: a DeepGBuffer of R, G, B, A (premultiplied) and the samples' Z and ZBack, front to
back, for deep compositing. The keywords are light()'s.)");
        },
        lightKeywords());
}

} // namespace dhdr::python
