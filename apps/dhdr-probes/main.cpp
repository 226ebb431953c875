// dhdr-probes: bakes light probes for diffuse global illumination (docs/gi.md), for a still
// scene or for each frame of an animated one (docs/animation.md, "Lighting a shot").
#include "../common/frame_timing.h"
#include "../common/frames.h"
#include "../common/light_options.h"
#include "../common/param_options.h"
#include "../common/tool.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <dhdr/deferred/geometry/posed_scene.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/scene/animation.h>
#include <dhdr/deferred/scene/lights.h>
#include <dhdr/deferred/scene/scene.h>

using namespace dhdr;

namespace {

// What -v says of a frame's probes (`when` they are of) and its `timing`, and the warning when
// none lights anything.
void reportFrame(const app::Tool& tool, const ProbeVolume& volume, const std::string& path,
                 const std::string& outPath, const std::string& when, size_t lights,
                 const std::string& timing) {
    int active = 0, relocated = 0, off = 0;
    for (const ProbeState s : volume.states) {
        active += s == ProbeState::Active;
        relocated += s == ProbeState::Relocated;
        off += s == ProbeState::Off;
    }
    char line[400];
    std::snprintf(line, sizeof line,
                  "%s%d probes (%dx%dx%d, spacing %.3g %.3g %.3g): %d in place, %d "
                  "relocated, %d off; %d rays each, %d bounces, %zu lights",
                  when.c_str(), volume.probeCount(), volume.counts.x, volume.counts.y,
                  volume.counts.z, volume.spacing.x, volume.spacing.y, volume.spacing.z, active,
                  relocated, off, volume.rays, volume.bounces, lights);
    tool.info(outPath + ": " + line);
    tool.info(timing);
    if (active + relocated == 0)
        tool.warn(path + ": every probe is inside geometry: the volume lights nothing");
}

// What the command line says.
struct Options {
    app::LightOptions lightOptions;
    ProbeBakeParams p;
    bool strict = false;
    app::FrameTiming timing;
};

void declareOptions(app::CommandLine& cl, Options& o) {
    app::addLightOptions(cl, o.lightOptions);
    app::addParamOptions(cl, o.p, kProbeBakeFloatTable);
    app::addParamOptions(cl, o.p, kProbeGridTable);
    app::addParamOptions(cl, o.p, kProbeBakeParamTable);
    cl.flag("--strict", o.strict,
            "a texture the scene names that cannot be read is an error (default: a warning, and "
            "the material shows magenta (1, 0, 1) times its factor)");
    o.timing.declare(cl);
    cl.epilog(
        "Examples:\n  dhdr-probes testdata/cornell_box.gltf --spacing 0.1 -o cornell.probes.exr\n"
        "  dhdr-light frame.gbuf.exr --scene testdata/cornell_box.gltf --probes "
        "cornell.probes.exr -o frame.hdr.exr\n"
        "  dhdr-probes shot.gltf --frames 1-24 -o shot.probes.####.exr\n"
        "  dhdr-light shot.gbuf.####.exr --scene shot.gltf --probes shot.probes.####.exr "
        "-o shot.hdr.####.exr");
}

int run(int argc, char** argv) {
    app::CommandLine cl(
        "dhdr-probes", "SCENE [--lights FILE...] -o PROBES.exr [options]",
        "Bakes a grid of light probes through a glTF/OBJ scene for dhdr-light --probes\n"
        "(DDGI, Majercik et al. 2019): probes inside geometry are moved into free space or\n"
        "switched off; each casts a spherical Fibonacci set of rays whose hits are lit by the\n"
        "lights (with shadows) and by the previous bounce's probes, and whose misses see the\n"
        "environment; each stores an octahedral map of irradiance and one of distance\n"
        "moments. One two-part EXR: the irradiance and distance atlases, the grid in the\n"
        "header. An animated scene is baked posed at a frame's time, as dhdr-gbuffer renders\n"
        "it (--frame, --time, --fps, --animation; frame 0 by default), or at every frame of\n"
        "--frames A-B into -o probes.####.exr, the scene loaded once; the file records the\n"
        "moment as a G-buffer does.");
    Options o;
    declareOptions(cl, o);
    app::LightOptions& lightOptions = o.lightOptions;
    ProbeBakeParams& p = o.p;
    const bool& strict = o.strict;
    app::FrameTiming& timing = o.timing;
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-probes", cl);
    if (cl.inputs().size() != 1 || cl.output().empty()) {
        std::fprintf(stderr, "dhdr-probes: usage error: give one scene and -o OUTPUT\n");
        return app::kExitUsage;
    }
    if (const int status = timing.check(tool); status >= 0) return status;
    if (const std::string problem = app::lightOptionsProblem(lightOptions, true);
        !problem.empty()) {
        std::fprintf(stderr, "dhdr-probes: usage error: %s\n", problem.c_str());
        return app::kExitUsage;
    }
    p.diffuse = app::diffuseModel(lightOptions);
    // The frames, as every tool plans them: the output checked (not an input, in a folder
    // that exists) for each frame; the scene and lights files may be patterns too (a lights
    // file a frame, from dhdr-gbuffer --lights-out).
    std::vector<std::string> paths = {cl.inputs()[0]};
    paths.insert(paths.end(), lightOptions.files.begin(), lightOptions.files.end());
    app::FramePlan plan;
    if (const int status = app::planFrames(tool, paths, plan); status >= 0) return status;
    // Lights files without a pattern hold the same lights for every frame: read once.
    const bool framedLights =
        std::any_of(plan.inputs.begin() + 1, plan.inputs.end(),
                    [](const app::FramePattern& f) { return f.isSequence(); });
    std::vector<Light> fileLights;
    if (!framedLights && !app::addLightsFiles(tool, lightOptions.files, lightOptions, fileLights))
        return app::kExitFailure;

    // The scene is loaded once for all the frames that name the same file and posed at each
    // frame's time, its BVH refitted, as dhdr-gbuffer does.
    PosedScene loaded;
    std::string loadedPath;
    bool loadFailed = false; // reported once
    auto load = [&](const std::string& path) {
        if (loadedPath == path) return !loadFailed;
        loadedPath = path;
        loadFailed = true; // until it is ready
        std::string error;
        if (!loaded.load(path, SceneOptions{strict}, error)) return tool.fail(error), false;
        // dhdr-probes is often the first to read the scene (before dhdr-gbuffer, which warns
        // the same way): what the loader repaired, a missing texture among it, is a warning.
        for (const std::string& warning : loaded.scene().warnings)
            tool.warn(path + ": " + warning);
        if (!loaded.selectAnimations(timing.animation, error)) {
            tool.fail(path + ": " + error);
            return false;
        }
        if (!loaded.animated() && timing.given)
            tool.warn(path + ": " + kNoAnimationPlayed +
                      "; --frame, --time and --fps change nothing");
        // Frames of one scene file under the same lights bake the same probes.
        if (!loaded.animated() && !framedLights && !plan.inputs[0].isSequence() &&
            plan.frames.size() > 1)
            tool.warn(path + ": " + kNoAnimationPlayed + "; --frames writes the same probes " +
                      std::to_string(plan.frames.size()) + " times");
        loadFailed = false;
        return true;
    };
    // A still scene under the same lights bakes the same probes at every frame: baked once.
    ProbeVolume volume;
    std::string bakedFor;

    return app::runFrames(tool, plan, [&](int frame, const auto& in, const std::string& outPath) {
        const std::string& path = in[0];
        const auto t0 = std::chrono::steady_clock::now();
        if (!load(path)) return false;
        const double time = timing.timeOf(frame);
        std::string error;
        if (!loaded.pose(time, error)) {
            tool.fail(path + ": " + error);
            return false;
        }
        // The lights in dhdr-light's order, the scene's as posed at this frame: the probes'
        // hits are lit as the frame's pixels are.
        std::vector<Light> lights = frame == plan.frames.front()
                                        ? app::sceneLights(tool, loaded.scene(), path, lightOptions)
                                        : app::sceneLights(loaded.scene(), lightOptions);
        if (framedLights &&
            !app::addLightsFiles(tool, {in.begin() + 1, in.end()}, lightOptions, lights))
            return false;
        lights.insert(lights.end(), fileLights.begin(), fileLights.end());
        const auto t1 = std::chrono::steady_clock::now();
        const bool again = loaded.animated() || framedLights || bakedFor != path;
        if (again) {
            app::Progress progress(tool, "dhdr-probes: baking");
            p.progress = [&](float f) { progress.update(f); };
            if (!bakeProbes(loaded.scene(), *loaded.caster(), lights,
                            lightOptions.emissive != "off", p, volume, error, tool.threads())) {
                bakedFor.clear();
                tool.fail(path + ": " + error);
                return false;
            }
            bakedFor = path;
            if (const NonFiniteCount& n = volume.replaced; n.total() > 0)
                tool.warn(outPath + ": " + std::to_string(n.total()) +
                          " distance moments past float's range (" + std::to_string(n.nan) +
                          " NaN → 0, " + std::to_string(n.positiveInf + n.negativeInf) +
                          " ±Inf → ±3.4e38): a scene too large for float");
            // Which moment of the animation these probes hold, recorded as G-buffers record
            // theirs, so that dhdr-light can tell when a G-buffer shows another.
            volume.moment = loaded.moment(time, timing.moment.fps);
        }
        const auto t2 = std::chrono::steady_clock::now();
        if (!tool.writeAtomically(outPath, [&](const std::string& temporary, std::string& why) {
                return writeProbes(temporary, volume, why);
            }))
            return false;
        const auto t3 = std::chrono::steady_clock::now();
        auto ms = [](auto a, auto b) {
            return std::to_string(int(std::chrono::duration<double, std::milli>(b - a).count())) +
                   " ms";
        };
        reportFrame(
            tool, volume, path, outPath,
            loaded.animated() ? "time " + std::to_string(time) + " s: " : "", lights.size(),
            (frame == plan.frames.front() ? "load and pose " : "pose ") + ms(t0, t1) +
                (again ? ", bake " + ms(t1, t2) : ", the last frame's bake (a still scene)") +
                ", write " + ms(t2, t3));
        return true;
    });
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-probes", [&] { return run(argc, argv); });
}
