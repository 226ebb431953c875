// The bakes: dhdr-ibl (an environment's SH, prefiltered levels and DFG table) and dhdr-probes
// (light probes through a scene), each writing the file the tools write, which light() and
// lights files then read; probes may also stay in memory (dhdr.Probes).
#include "py_image.h"
#include "py_interrupt.h"
#include "py_lights.h"
#include "py_ops.h"
#include "py_probes.h"
#include "py_scene.h"

#include <cstring>
#include <dhdr/deferred/environment/environment.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/lights/emissive_lights.h>
#include <dhdr/io/image_output.h>
#include <pybind11/stl.h>

namespace dhdr::python {

namespace {

using namespace pybind11::literals;

py::dict bakeIblFile(const py::object& environment, const std::string& out, int levels,
                     int baseWidth, int samples, int dfgSize, int dfgSamples, float sunThreshold,
                     int nthreads) {
    IblBakeParams p;
    p.levels = levels;
    p.baseWidth = baseWidth;
    p.samples = samples;
    p.dfgSize = dfgSize;
    p.dfgSamples = dfgSamples;
    p.sunThreshold = sunThreshold;
    checkParams(p, kIblBakeParamTable);
    checkParams(p, kIblBakeFloatTable);
    checkImageName(out, "out");
    // A file as dhdr-ibl reads it, or an image in memory (its R, G, B by name).
    const bool file = py::isinstance<py::str>(environment);
    const std::string name = file ? environment.cast<std::string>() : "environment";
    Image storage;
    ImageView pixels;
    if (!file) pixels = view(asImage(environment, "environment", storage));
    EnvironmentImage env;
    Ibl ibl;
    std::string error;
    long long replaced = 0;
    bool ok = false;
    // Ctrl-C stops the bake at its next row and raises KeyboardInterrupt; nothing is written
    // unless the bake completed (py_interrupt.h).
    std::atomic<bool> cancel{false};
    p.cancel = &cancel;
    runInterruptibly(cancel, [&] {
        const bool read =
            file ? readEnvironmentImage(name, env, error, &replaced)
                 : environmentFromPixels(pixels.buf.spec(), pixels.data, env, error, &replaced);
        if (!read || !bakeIbl(env, p, ibl, error, nthreads))
            error = name + ": " + error;
        else if (!cancel)
            ok = writeFileAtomically(
                out,
                [&](const std::string& tmp, std::string& why) { return writeIbl(tmp, ibl, why); },
                error);
    });
    if (!ok) raiseError(error);
    if (replaced > 0)
        warn(name + ": " + std::to_string(replaced) +
             " NaN or infinite texel values replaced by 0");
    py::dict sun("found"_a = ibl.sun.found());
    if (ibl.sun.found()) {
        sun["direction"] =
            py::make_tuple(ibl.sun.direction.x, ibl.sun.direction.y, ibl.sun.direction.z);
        sun["illuminance"] =
            py::make_tuple(ibl.sun.illuminance.r, ibl.sun.illuminance.g, ibl.sun.illuminance.b);
        sun["angle_degrees"] = double(ibl.sun.angle) * 57.29577951308232;
        sun["share"] = ibl.sun.share;
    }
    return py::dict("width"_a = env.width, "height"_a = env.height, "sun"_a = sun);
}

py::dict infoOf(const ProbeVolume& v) {
    int active = 0, relocated = 0, off = 0;
    for (const ProbeState s : v.states) {
        active += s == ProbeState::Active;
        relocated += s == ProbeState::Relocated;
        off += s == ProbeState::Off;
    }
    return py::dict("counts"_a = py::make_tuple(v.counts.x, v.counts.y, v.counts.z),
                    "spacing"_a = py::make_tuple(v.spacing.x, v.spacing.y, v.spacing.z),
                    "active"_a = active, "relocated"_a = relocated, "off"_a = off,
                    "bounces"_a = v.bounces);
}

ProbesHandle readProbesFile(const std::string& path) {
    auto volume = std::make_shared<ProbeVolume>();
    std::string error;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        ok = readProbes(path, *volume, error);
    }
    if (!ok) throw py::value_error(path + ": " + error);
    return ProbesHandle{volume, -1};
}

py::object bakeProbesTo(const SceneHandle& scene, const py::object& outGiven,
                        const py::object& lightsGiven, double spacing, const py::object& grid,
                        int maxProbes, int rays, int bounces, int shadowSamples, bool emissive,
                        bool radiometric, const std::string& diffuse, int nthreads) {
    ProbeBakeParams p;
    p.spacing = spacing;
    if (!grid.is_none()) {
        const std::vector<int> v = grid.cast<std::vector<int>>();
        if (v.size() != 3) throw py::value_error("grid needs three whole numbers (NX, NY, NZ)");
        p.counts = glm::ivec3(v[0], v[1], v[2]);
        // Given, so (0, 0, 0) too is refused, as dhdr-probes --grid 0,0,0 is.
        if (const std::string e = rangeProblem(kProbeGridTable[0], p.counts, Spelling::Keyword);
            !e.empty())
            throw py::value_error(e);
    }
    p.maxProbes = maxProbes;
    p.rays = rays;
    p.bounces = bounces;
    p.shadowSamples = shadowSamples;
    checkParams(p, kProbeBakeParamTable);
    checkParams(p, kProbeBakeFloatTable);
    if (diffuse != "lambert" && diffuse != "burley")
        throw py::value_error("diffuse must be lambert or burley");
    p.diffuse = diffuse == "burley" ? DiffuseModel::Burley : DiffuseModel::Lambert;
    // dhdr-light's lights, in its order: the probes' hits are lit as the frame's pixels are.
    std::vector<Light> lights =
        sceneLightList(*scene.scene, lightsGiven.is_none(), emissive, radiometric);
    if (!lightsGiven.is_none()) {
        const std::vector<Light> more = lightsOf(lightsGiven, radiometric);
        lights.insert(lights.end(), more.begin(), more.end());
    }
    const std::string out = outGiven.is_none() ? "" : std::string(py::str(outGiven));
    checkImageName(out, "out");
    const RayCaster& caster = scene.caster();
    auto volume = std::make_shared<ProbeVolume>();
    std::string error;
    bool ok = false;
    // Ctrl-C stops the probes not begun and raises KeyboardInterrupt before anything is written
    // (py_interrupt.h); a file being written when it comes is completed (written atomically).
    std::atomic<bool> cancel{false};
    p.cancel = &cancel;
    runInterruptibly(cancel, [&] {
        if (!bakeProbes(*scene.scene, caster, lights, emissive, p, *volume, error, nthreads)) {
            error = scene.path + ": " + error;
        } else if (out.empty()) {
            roundAsStored(*volume);
            ok = true;
        } else if (!cancel) {
            ok = writeFileAtomically(
                out,
                [&](const std::string& tmp, std::string& why) {
                    return writeProbes(tmp, *volume, why);
                },
                error);
        }
    });
    if (!ok) raiseError(error);
    if (out.empty()) return py::cast(ProbesHandle{volume, int(lights.size())});
    py::dict info = infoOf(*volume);
    info["lights"] = lights.size();
    return std::move(info);
}

} // namespace

std::shared_ptr<const ProbeVolume> probesOf(const py::handle& given) {
    if (given.is_none()) return nullptr;
    if (py::isinstance<ProbesHandle>(given)) return given.cast<const ProbesHandle&>().volume;
    if (py::isinstance<py::str>(given) ||
        py::isinstance(given, py::module_::import("os").attr("PathLike"))) {
        const std::string path = py::str(given);
        if (path.empty()) return nullptr;
        return readProbesFile(path).volume;
    }
    throw py::type_error("probes: expected a dhdr-probes file or a dhdr.Probes");
}

void bindBakes(py::module_& m) {
    py::class_<ProbesHandle>(m, "Probes", R"(Light probes in memory (docs/gi.md): what bake_probes
bakes when it is given no file, or read_probes reads from a dhdr-probes file. light(probes=)
takes it as it takes the file, with the same bits; write(path) writes that file.)")
        .def_property_readonly("counts",
                               [](const ProbesHandle& h) {
                                   const glm::ivec3 c = h.volume->counts;
                                   return py::make_tuple(c.x, c.y, c.z);
                               })
        .def_property_readonly("origin",
                               [](const ProbesHandle& h) {
                                   const glm::dvec3 o = h.volume->origin;
                                   return py::make_tuple(o.x, o.y, o.z);
                               })
        .def_property_readonly("spacing",
                               [](const ProbesHandle& h) {
                                   const glm::dvec3 s = h.volume->spacing;
                                   return py::make_tuple(s.x, s.y, s.z);
                               })
        .def_property_readonly("rays", [](const ProbesHandle& h) { return h.volume->rays; })
        .def_property_readonly("bounces", [](const ProbesHandle& h) { return h.volume->bounces; })
        .def_property_readonly(
            "positions",
            [](const ProbesHandle& h) {
                const std::vector<glm::vec3>& p = h.volume->positions;
                py::array_t<float> out({py::ssize_t(p.size()), py::ssize_t(3)});
                std::memcpy(out.mutable_data(), p.data(), p.size() * sizeof(glm::vec3));
                return out;
            },
            "Each probe's position (x fastest, then y, then z), relocated ones moved: (n, 3).")
        .def_property_readonly(
            "info",
            [](const ProbesHandle& h) {
                py::dict info = infoOf(*h.volume);
                if (h.lights >= 0) info["lights"] = h.lights;
                return info;
            },
            "What bake_probes returns with a file: counts, spacing, how many probes are active, "
            "relocated and off, bounces (and the lights baked with).")
        .def(
            "write",
            [](const ProbesHandle& h, const std::string& path) {
                checkImageName(path, "path");
                const std::shared_ptr<const ProbeVolume> v = h.volume;
                std::string error;
                bool ok = false;
                {
                    py::gil_scoped_release gil;
                    ok = writeFileAtomically(
                        path,
                        [&](const std::string& tmp, std::string& why) {
                            return writeProbes(tmp, *v, why);
                        },
                        error);
                }
                if (!ok) raiseError(error);
            },
            "path"_a, "Writes the probes as dhdr-probes does, atomically.")
        .def("__repr__", [](const ProbesHandle& h) {
            const glm::ivec3 c = h.volume->counts;
            return "dhdr.Probes(" + std::to_string(c.x) + "x" + std::to_string(c.y) + "x" +
                   std::to_string(c.z) + ")";
        });
    m.def("read_probes", &readProbesFile, "path"_a,
          "A dhdr-probes file as a dhdr.Probes, read once for many light(probes=...) calls.");

    const IblBakeParams ibl;
    m.def(
        "bake_ibl", &bakeIblFile, "environment"_a, "out"_a, py::kw_only(), "levels"_a = ibl.levels,
        "base_width"_a = ibl.baseWidth, "samples"_a = ibl.samples, "dfg_size"_a = ibl.dfgSize,
        "dfg_samples"_a = ibl.dfgSamples, "sun_threshold"_a = ibl.sunThreshold, "nthreads"_a = 0,
        R"(dhdr-ibl: bakes an equirectangular environment file (2:1) into out: 9 SH coefficients of
its irradiance, levels GGX-prefiltered levels from base_width wide (samples per texel at
level 1), the DFG table (dfg_size, dfg_samples), and the sun above sun_threshold split off.
A lights file's {"type": "environment", "image": out} then uses it. Returns the size and
the sun found.)");
    const ProbeBakeParams probes;
    m.def("bake_probes", &bakeProbesTo, "scene"_a, "out"_a = py::none(), "lights"_a = py::none(),
          py::kw_only(), "spacing"_a = 0.0, "grid"_a = py::none(),
          "max_probes"_a = probes.maxProbes, "rays"_a = probes.rays, "bounces"_a = probes.bounces,
          "shadow_samples"_a = probes.shadowSamples, "emissive_lights"_a = true,
          "radiometric"_a = false, "diffuse"_a = "lambert", "nthreads"_a = 0,
          R"(dhdr-probes: bakes light probes through a dhdr.Scene into out (light(probes=out) reads
it). lights as light() takes them (default the scene's own), then its emissive meshes;
spacing (scene units, at most: the outer probes a quarter spacing inside the bounds) or grid
(NX, NY, NZ), else the finest grid of at most max_probes;
rays per probe, bounces (0: until converged), shadow_samples, diffuse as dhdr-probes'
options. Returns the grid and how many probes are active, relocated and off. Without out
(None), nothing is written: returns a dhdr.Probes that light(probes=) takes.)");
}

} // namespace dhdr::python
