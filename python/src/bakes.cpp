// The bakes: dhdr-ibl (an environment's SH, prefiltered levels and DFG table) and dhdr-probes
// (light probes through a scene), each writing the file the tools write, which light() and
// lights files then read.
#include "python_lights.h"
#include "scene.h"

#include <dhdr/deferred/emissive_lights.h>
#include <dhdr/deferred/environment.h>
#include <dhdr/deferred/ibl.h>
#include <dhdr/deferred/probes.h>
#include <dhdr/io/image_output.h>
#include <pybind11/stl.h>

namespace dhdr::python {

namespace {

using namespace pybind11::literals;

// The parameters' ranges are dhdr-ibl's options'.
void checkInt(const char* name, int v, int lo, int hi) {
    if (v < lo || v > hi)
        throw py::value_error(std::string(name) + ": " + std::to_string(v) + " is outside [" +
                              std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

py::dict bakeIblFile(const py::object& environment, const std::string& out, int levels,
                     int baseWidth, int samples, int dfgSize, int dfgSamples, float sunThreshold,
                     int nthreads) {
    IblBakeParams p;
    checkInt("levels", levels, 2, 16);
    checkInt("base_width", baseWidth, 8, 4096);
    checkInt("samples", samples, 1, 65536);
    checkInt("dfg_size", dfgSize, 2, 1024);
    checkInt("dfg_samples", dfgSamples, 1, 65536);
    if (!(sunThreshold >= 0.0f && sunThreshold <= 1e30f))
        throw py::value_error("sun_threshold: must be in [0, 1e30]");
    p.levels = levels;
    p.baseWidth = baseWidth;
    p.samples = samples;
    p.dfgSize = dfgSize;
    p.dfgSamples = dfgSamples;
    p.sunThreshold = sunThreshold;
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
    {
        py::gil_scoped_release gil;
        const bool read =
            file ? readEnvironmentImage(name, env, error, &replaced)
                 : environmentFromPixels(pixels.buf.spec(), pixels.data, env, error, &replaced);
        if (!read || !bakeIbl(env, p, ibl, error, nthreads))
            error = name + ": " + error;
        else
            ok = writeFileAtomically(
                out,
                [&](const std::string& tmp, std::string& why) { return writeIbl(tmp, ibl, why); },
                error);
    }
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

py::dict bakeProbesFile(const SceneHandle& scene, const std::string& out,
                        const py::object& lightsGiven, double spacing, const py::object& grid,
                        int maxProbes, int rays, int bounces, int shadowSamples, bool emissive,
                        bool radiometric, const std::string& diffuse, int nthreads) {
    ProbeBakeParams p;
    if (!(spacing >= 0.0 && spacing <= 1e6)) throw py::value_error("spacing: must be in [0, 1e6]");
    p.spacing = spacing;
    if (!grid.is_none()) {
        const std::vector<int> v = grid.cast<std::vector<int>>();
        if (v.size() != 3 || *std::min_element(v.begin(), v.end()) < 1 ||
            *std::max_element(v.begin(), v.end()) > 256)
            throw py::value_error("grid needs three whole numbers 1-256");
        p.counts = glm::ivec3(v[0], v[1], v[2]);
    }
    p.maxProbes = maxProbes;
    p.rays = rays;
    p.bounces = bounces;
    p.shadowSamples = shadowSamples;
    if (const std::string e = checkRanges(p, kProbeBakeParamTable); !e.empty())
        throw py::value_error(e);
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
    const RayCaster& caster = scene.caster();
    ProbeVolume volume;
    std::string error;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        if (!bakeProbes(*scene.scene, caster, lights, emissive, p, volume, error, nthreads))
            error = scene.path + ": " + error;
        else
            ok = writeFileAtomically(
                out,
                [&](const std::string& tmp, std::string& why) {
                    return writeProbes(tmp, volume, why);
                },
                error);
    }
    if (!ok) raiseError(error);
    int active = 0, relocated = 0, off = 0;
    for (const ProbeState s : volume.states) {
        active += s == ProbeState::Active;
        relocated += s == ProbeState::Relocated;
        off += s == ProbeState::Off;
    }
    return py::dict("counts"_a = py::make_tuple(volume.counts.x, volume.counts.y, volume.counts.z),
                    "spacing"_a =
                        py::make_tuple(volume.spacing.x, volume.spacing.y, volume.spacing.z),
                    "active"_a = active, "relocated"_a = relocated, "off"_a = off,
                    "bounces"_a = volume.bounces, "lights"_a = lights.size());
}

} // namespace

void bindBakes(py::module_& m) {
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
    m.def("bake_probes", &bakeProbesFile, "scene"_a, "out"_a, "lights"_a = py::none(),
          py::kw_only(), "spacing"_a = 0.0, "grid"_a = py::none(),
          "max_probes"_a = probes.maxProbes, "rays"_a = probes.rays, "bounces"_a = probes.bounces,
          "shadow_samples"_a = probes.shadowSamples, "emissive_lights"_a = true,
          "radiometric"_a = false, "diffuse"_a = "lambert", "nthreads"_a = 0,
          R"(dhdr-probes: bakes light probes through a dhdr.Scene into out (light(probes=out) reads
it). lights as light() takes them (default the scene's own), then its emissive meshes;
spacing (scene units) or grid (NX, NY, NZ), else the finest grid of at most max_probes;
rays per probe, bounces (0: until converged), shadow_samples, diffuse as dhdr-probes'
options. Returns the grid and how many probes are active, relocated and off.)");
}

} // namespace dhdr::python
