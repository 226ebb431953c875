// dhdr-probes: bakes light probes for diffuse global illumination (docs/gi.md).
#include "../common/light_options.h"
#include "../common/param_options.h"
#include "../common/tool.h"

#include <chrono>
#include <cstdio>
#include <dhdr/deferred/lights.h>
#include <dhdr/deferred/probes.h>
#include <dhdr/deferred/ray_caster.h>
#include <dhdr/deferred/scene.h>

using namespace dhdr;

namespace {

int run(int argc, char** argv) {
    app::CommandLine cl(
        "dhdr-probes", "SCENE [--lights FILE...] -o PROBES.exr [options]",
        "Bakes a grid of light probes through a static glTF/OBJ scene for dhdr-light --probes\n"
        "(DDGI, Majercik et al. 2019): probes inside geometry are moved into free space or\n"
        "switched off; each casts a spherical Fibonacci set of rays whose hits are lit by the\n"
        "lights (with shadows) and by the previous bounce's probes, and whose misses see the\n"
        "environment; each stores an octahedral map of irradiance and one of distance\n"
        "moments. One two-part EXR: the irradiance and distance atlases, the grid in the\n"
        "header.");
    app::LightOptions lightOptions;
    std::string grid;
    ProbeBakeParams p;
    double spacing = 0.0;
    app::addLightOptions(cl, lightOptions);
    cl.option("--spacing", spacing, "M",
              "distance between probes in scene units (default: from the scene's bounds, "
              "--max-probes)",
              {0.0, 1e6, true, false});
    cl.option("--grid", grid, "NX,NY,NZ", "probe counts along X, Y, Z instead of --spacing");
    app::addParamOptions(cl, p, kProbeBakeParamTable);
    bool strict = false;
    cl.flag("--strict", strict,
            "a texture the scene names that cannot be read is an error (default: a warning, and "
            "the material shows magenta (1, 0, 1) times its factor)");
    cl.epilog(
        "Example:\n  dhdr-probes testdata/cornell_box.gltf --spacing 0.1 -o cornell.probes.exr\n"
        "  dhdr-light frame.gbuf.exr --scene testdata/cornell_box.gltf --probes "
        "cornell.probes.exr -o frame.hdr.exr");
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-probes", cl);
    if (cl.inputs().size() != 1 || cl.output().empty()) {
        std::fprintf(stderr, "dhdr-probes: usage error: give one scene and -o OUTPUT\n");
        return app::kExitUsage;
    }
    // The output checks every tool makes: not an input, in a folder that exists.
    if (const int status = tool.start(cl.inputs()); status >= 0) return status;
    if (const std::string problem = app::lightOptionsProblem(lightOptions, true);
        !problem.empty()) {
        std::fprintf(stderr, "dhdr-probes: usage error: %s\n", problem.c_str());
        return app::kExitUsage;
    }
    p.spacing = spacing;
    p.diffuse = app::diffuseModel(lightOptions);
    if (!grid.empty()) {
        std::vector<double> v;
        if (!app::parseNumbers(grid, v) || v.size() != 3 || v[0] < 1 || v[1] < 1 || v[2] < 1 ||
            v[0] > 256 || v[1] > 256 || v[2] > 256 || v[0] != std::floor(v[0]) ||
            v[1] != std::floor(v[1]) || v[2] != std::floor(v[2])) {
            std::fprintf(stderr, "dhdr-probes: usage error: --grid needs three whole numbers "
                                 "1-256\n");
            return app::kExitUsage;
        }
        p.counts = glm::ivec3(int(v[0]), int(v[1]), int(v[2]));
    }
    const std::string& path = cl.inputs()[0];
    const auto t0 = std::chrono::steady_clock::now();
    Scene scene;
    std::string error;
    if (!loadScene(path, scene, error, SceneOptions{strict})) return tool.fail(error);
    // dhdr-probes is often the first to read the scene (before dhdr-gbuffer, which warns the
    // same way): what the loader repaired, a missing texture among it, is a warning.
    for (const std::string& warning : scene.warnings)
        tool.warn(path + ": " + warning);
    // The lights in dhdr-light's order: the probes' hits are lit as the frame's pixels are.
    std::vector<Light> lights = app::sceneLights(tool, scene, path, lightOptions);
    if (!app::addLightsFiles(tool, lightOptions.files, lightOptions, lights))
        return app::kExitFailure;
    const RayCaster caster(scene);
    if (!caster.ok()) return tool.fail(path + ": " + caster.error());
    const auto t1 = std::chrono::steady_clock::now();
    ProbeVolume volume;
    {
        app::Progress progress(tool, "dhdr-probes: baking");
        p.progress = [&](float f) { progress.update(f); };
        if (!bakeProbes(scene, caster, lights, lightOptions.emissive != "off", p, volume, error,
                        tool.threads()))
            return tool.fail(path + ": " + error);
    }
    const auto t2 = std::chrono::steady_clock::now();
    if (!tool.writeAtomically(cl.output(), [&](const std::string& temporary, std::string& why) {
            return writeProbes(temporary, volume, why);
        }))
        return app::kExitFailure;
    const auto t3 = std::chrono::steady_clock::now();
    int active = 0, relocated = 0, off = 0;
    for (const ProbeState s : volume.states) {
        active += s == ProbeState::Active;
        relocated += s == ProbeState::Relocated;
        off += s == ProbeState::Off;
    }
    char line[300];
    std::snprintf(line, sizeof line,
                  "%d probes (%dx%dx%d, spacing %.3g %.3g %.3g): %d in place, %d relocated, %d "
                  "off; %d rays each, %d bounces, %zu lights",
                  volume.probeCount(), volume.counts.x, volume.counts.y, volume.counts.z,
                  volume.spacing.x, volume.spacing.y, volume.spacing.z, active, relocated, off,
                  volume.rays, volume.bounces, lights.size());
    tool.info(line);
    auto ms = [](auto a, auto b) {
        return std::to_string(int(std::chrono::duration<double, std::milli>(b - a).count())) +
               " ms";
    };
    tool.info("load " + ms(t0, t1) + ", bake " + ms(t1, t2) + ", write " + ms(t2, t3));
    if (active + relocated == 0)
        tool.warn(path + ": every probe is inside geometry: the volume lights nothing");
    return app::kExitSuccess;
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-probes", [&] { return run(argc, argv); });
}
