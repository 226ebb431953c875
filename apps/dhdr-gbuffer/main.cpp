// dhdr-gbuffer: a scene in, a multi-channel EXR G-buffer out (docs/tools.md).
#include "../common/animated_scene.h"
#include "../common/frame_timing.h"
#include "../common/frames.h"
#include "../common/tool.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_time.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_camera.h>
#include <dhdr/deferred/scene/scene_info.h>
#include <dhdr/io/strip_pipeline.h>
#include <glm/gtc/constants.hpp>
#include <optional>

using namespace dhdr;

namespace {

int run(int argc, char** argv) {
    app::CommandLine cl(
        "dhdr-gbuffer", "SCENE -o GBUFFER.exr [options]",
        "Casts one primary ray per pixel (Embree) through a glTF 2.0 or OBJ scene "
        "(Assimp) and\nwrites the G-buffer channels of docs/gbuffer.md: A Z P.* N.* "
        "albedo.* roughness\nmetallic emission.* id.object id.material.");
    std::string size = "1920x1080", cameraName, lookat, lightsOut;
    double fov = 0.0;
    cl.option("--size", size, "WxH", "image size in pixels (default 1920x1080)");
    cl.option("--camera", cameraName, "NAME", "the scene camera to use (default: the first)");
    cl.option("--lookat", lookat, "EX,EY,EZ,TX,TY,TZ[,UX,UY,UZ]",
              "a camera at E looking at T (up U, default 0,1,0) instead of the scene's");
    cl.option("--fov", fov, "DEG",
              "vertical field of view in degrees (default: the scene "
              "camera's, or 39.6 with --lookat)",
              {0.0, 180.0, true, true});
    cl.option("--lights-out", lightsOut, "FILE",
              "also write the scene's punctual lights as a lights file (docs/lights.md)");
    bool frameAll = false, info = false, groundPlane = false, deep = false, flat = false;
    int maxLayers = 8;
    cl.flag("--deep", deep,
            "always write a deep EXR: per pixel every surface up to the first opaque one "
            "(default: only when some pixel holds a partly transparent surface)");
    cl.flag("--flat", flat,
            "never write a deep EXR: each pixel's first surface, transparent or not");
    cl.option("--max-layers", maxLayers, "N",
              "deep G-buffers: at most N samples a pixel (1-64, default 8); the opaque surface "
              "keeps its place, Blend surfaces beyond the first N-1 are left out",
              1, 64);
    std::optional<double> groundY;
    cl.flagWithNumber("--ground-plane", groundPlane, groundY, "Y",
                      "add an infinite horizontal plane at height Y (default: the scene's lowest "
                      "point) that dhdr-light treats as a shadow catcher for compositing "
                      "(docs/ibl.md)",
                      {-1e30, 1e30});
    cl.flag("--frame-all", frameAll,
            "move the camera (the scene's, --lookat's, or without either one looking from the "
            "front and a little above) back until the whole scene fits the image (an error when "
            "no float camera can: coordinates near 3e38)");
    bool strict = false;
    cl.flag("--strict", strict,
            "a texture the scene names that cannot be read is an error (default: a warning, and "
            "the material shows magenta (1, 0, 1) times its factor, as in Blender)");
    app::FrameTiming timing;
    timing.declare(cl);
    cl.flag(
        "--info", info,
        "print what the scene holds (bounds, cameras, lights, materials, animations, what is left "
        "out) and exit; needs no -o");
    cl.epilog(
        "Example:\n  dhdr-gbuffer testdata/cornell_box.gltf --size 1280x720 -o frame.gbuf.exr");
    cl.namesFile("--lights-out", app::FileRole::Output);
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-gbuffer", cl);
    if (cl.inputs().size() != 1) {
        std::fprintf(stderr, "dhdr-gbuffer: usage error: give one scene file\n");
        return app::kExitUsage;
    }
    const std::string& path = cl.inputs()[0];
    if (info) {
        Scene scene;
        std::string error;
        if (!loadScene(path, scene, error, SceneOptions{strict})) return tool.fail(error);
        std::fputs(describeScene(scene, path).c_str(), stdout);
        return app::kExitSuccess;
    }
    if (const int status = timing.check(tool); status >= 0) return status;
    app::FramePlan plan;
    if (const int status = app::planFrames(tool, cl.inputs(), plan); status >= 0) return status;
    const app::FramePattern lightsOutput(lightsOut);

    if (deep && flat) {
        std::fprintf(stderr, "dhdr-gbuffer: usage error: --deep and --flat exclude each other\n");
        return app::kExitUsage;
    }
    GBufferParams params;
    params.maxLayers = maxLayers;
    if (!app::parseSize(size, params.width, params.height)) {
        std::fprintf(stderr, "dhdr-gbuffer: usage error: --size '%s' is not WxH\n", size.c_str());
        return app::kExitUsage;
    }
    if (const std::string e = pixelLimitError(params.width, params.height); !e.empty()) {
        std::fprintf(stderr, "dhdr-gbuffer: usage error: --size %s: %s\n", size.c_str(), e.c_str());
        return app::kExitUsage;
    }

    std::optional<Camera> lookatCamera;
    if (!lookat.empty()) {
        std::vector<double> v;
        std::string error;
        if (!app::parseFloatNumbers(lookat, v, 0, error) || (v.size() != 6 && v.size() != 9)) {
            // The camera's rays are traced in float (Embree).
            std::fprintf(stderr, "dhdr-gbuffer: usage error: --lookat%s\n",
                         error.empty() ? " needs 6 or 9 numbers" : (": " + error).c_str());
            return app::kExitUsage;
        }
        const glm::dvec3 up = v.size() == 9 ? glm::dvec3(v[6], v[7], v[8]) : glm::dvec3(0, 1, 0);
        const glm::dvec3 eye(v[0], v[1], v[2]), target(v[3], v[4], v[5]);
        if (glm::length(target - eye) < 1e-9 * std::max(1.0, glm::length(eye))) {
            std::fprintf(stderr, "dhdr-gbuffer: usage error: --lookat: the eye and the target "
                                 "are the same point\n");
            return app::kExitUsage;
        }
        if (glm::length(up) == 0.0) {
            std::fprintf(stderr, "dhdr-gbuffer: usage error: --lookat: the up vector is zero\n");
            return app::kExitUsage;
        }
        lookatCamera =
            Camera::lookAt({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, up, glm::radians(39.6));
    }

    auto writeLightsOut = [&](int frame, const Scene& scene, const std::string& scenePath) {
        if (lightsOut.empty()) return true;
        const std::string lightsPath = lightsOutput.path(frame);
        if (scene.lights.empty())
            tool.warn(scenePath + ": the scene has no lights; writing an empty list");
        if (!tool.writeText(formatLights(scene.lights), lightsPath)) return false;
        tool.info(std::to_string(scene.lights.size()) + " lights written to " + lightsPath);
        return true;
    };
    // The camera of a frame (chooseCamera: --lookat's, else the scene's, posed, with --fov
    // and --frame-all); what it says is said once a frame.
    bool announce = true;
    auto cameraOf = [&](const Scene& scene, const std::string& scenePath, Camera& camera) {
        CameraChoice choice;
        choice.name = cameraName;
        choice.lookat = lookatCamera;
        choice.fovDegrees = fov;
        choice.frameAll = frameAll;
        std::vector<std::string> notes, warnings;
        std::string error;
        const bool chosen =
            chooseCamera(scene, scenePath, choice, double(params.width) / double(params.height),
                         camera, error, notes, warnings);
        if (announce) {
            for (const std::string& w : warnings)
                tool.warn(w);
            for (const std::string& n : notes)
                tool.info(n);
        }
        if (!chosen) tool.fail(error);
        return chosen;
    };

    // The scene is loaded once for all frames that name the same file; animated, it is posed
    // at each frame's time.
    app::AnimatedScene loaded;
    bool toldMoves = false; // the loaded scene's motionSummary, once
    auto load = [&](const std::string& scenePath) {
        if (loaded.path == scenePath) return !loaded.failed;
        loaded = app::AnimatedScene{};
        toldMoves = false;
        loaded.path = scenePath;
        loaded.failed = true; // until it is ready: a failure is reported once
        Scene& scene = loaded.scene;
        std::string error;
        if (!loadScene(scenePath, scene, error, SceneOptions{strict}))
            return tool.fail(error), false;
        for (const std::string& warning : scene.warnings)
            tool.warn(scenePath + ": " + warning);
        if (!loaded.selectAnimations(timing.animation, error)) {
            tool.fail(scenePath + ": " + error);
            return false;
        }
        if (!loaded.animated() && timing.given)
            tool.warn(scenePath + ": the scene has no animation; --frame, --time and --fps "
                                  "change nothing");
        if (groundPlane) {
            const double y =
                groundY ? *groundY : (scene.meshes.empty() ? 0.0 : scene.boundsMin().y);
            addGroundPlane(scene, float(y));
            tool.info("ground plane (shadow catcher) at y = " + std::to_string(y));
        }
        loaded.failed = false;
        return true;
    };

    return app::runFrames(tool, plan, [&](int frame, const auto& in, const std::string& outPath) {
        const std::string& scenePath = in[0];
        const auto t0 = std::chrono::steady_clock::now();
        if (!load(scenePath)) return false;
        Scene& scene = loaded.scene;
        const double time = timing.timeOf(frame);
        std::shared_ptr<FrameMotion> motion;
        std::string error;
        announce = false;
        auto around = [&](const Scene& s, Camera& c) { return cameraOf(s, scenePath, c); };
        if (!loaded.pose(time, 1.0 / timing.fps, around, motion, error)) {
            if (!error.empty()) tool.fail(scenePath + ": " + error);
            return false;
        }
        announce = true;
        Camera camera;
        if (!cameraOf(scene, scenePath, camera)) return false;
        if (loaded.animated())
            tool.info("time " + std::to_string(time) + " s; motion layer written");
        if (const std::string moves = loaded.motionSummary(); !moves.empty() && !toldMoves) {
            tool.info(scenePath + ": " + moves);
            toldMoves = true;
        }

        const auto t1 = std::chrono::steady_clock::now();
        GBufferParams frameParams = params;
        frameParams.motion = motion;
        const GBufferRenderer renderer(scene, camera, frameParams, loaded.caster);
        if (!renderer.ok()) {
            tool.fail(scenePath + ": " + renderer.error());
            return false;
        }
        OIIO::ImageSpec spec = renderer.spec();
        spec.attribute("dhdr:source", scenePath);
        // When the file plays, which moment of it this is (seconds, the frame rate that put
        // frames there, the animations that played), so that a compositor can tell and
        // dhdr-light --scene poses the scene where the pixels are.
        auto stampTime = [&](OIIO::ImageSpec& s) {
            if (!loaded.animated()) return;
            gbuffer::Moment moment;
            moment.time = time;
            moment.fps = timing.fps;
            moment.animations = loaded.playing;
            gbuffer::writeMoment(s, moment);
        };
        stampTime(spec);
        if (const std::string sha = sceneFingerprint(scenePath); !sha.empty())
            spec.attribute(gbuffer::kSceneFingerprint, sha);
        constexpr int kStrip = 64;
        const bool blends =
            std::any_of(scene.materials.begin(), scene.materials.end(),
                        [](const Material& m) { return m.alphaMode == AlphaMode::Blend; });
        if (deep || (!flat && blends)) {
            // Without --deep, a deep file is written only when some pixel holds a partly
            // transparent surface: the layers are traced strip by strip until one is found
            // (all of them when none is), keeping nothing, then traced again and written a strip
            // at a time, so memory stays at one strip whatever the image size.
            const auto s0 = std::chrono::steady_clock::now();
            bool writeDeep = deep;
            DeepGBuffer strip;
            // The strips the search traced, kept while they fit kKeptBytes, so that a frame
            // of ordinary size is traced once.
            constexpr size_t kKeptBytes = size_t(256) << 20;
            std::vector<std::pair<DeepGBuffer, long long>> kept; // and its transparent samples
            size_t keptBytes = 0;
            if (!deep) {
                app::Progress progress(tool, "dhdr-gbuffer: looking for transparent surfaces");
                for (int y = 0; y < params.height && !writeDeep; y += kStrip) {
                    const OIIO::ROI rows(0, params.width, y, std::min(y + kStrip, params.height));
                    long long t = 0;
                    if (!renderer.renderDeep(strip, rows, tool.threads(), &t)) {
                        tool.fail(scenePath + ": cannot render the layers");
                        return false;
                    }
                    writeDeep = t > 0;
                    keptBytes += strip.values.size() * sizeof(float) +
                                 strip.first.size() * sizeof(std::uint32_t);
                    if (keptBytes <= kKeptBytes)
                        kept.emplace_back(strip, t);
                    else
                        kept.clear();
                    progress.update(float(rows.yend) / float(params.height));
                }
                if (!writeDeep || keptBytes > kKeptBytes) kept.clear();
            }
            if (writeDeep) {
                long long transparent = 0, samples = 0;
                std::vector<OIIO::TypeDesc> deepFormats = gbuffer::deepChannelFormats();
                if (motion) deepFormats.insert(deepFormats.end(), 4, OIIO::TypeDesc::FLOAT);
                app::AtomicOutput file(tool, outPath);
                app::Progress progress(tool, "dhdr-gbuffer: rendering layers");
                StripPipelineParams streaming;
                streaming.rows = kStrip;
                streaming.progress = progress.over();
                StripStages stages;
                stages.process = [&](OIIO::ROI rows, int, std::string& e) {
                    const size_t k = size_t(rows.ybegin / kStrip);
                    long long t = 0;
                    if (k < kept.size()) {
                        strip = std::move(kept[k].first);
                        t = kept[k].second;
                    } else if (!renderer.renderDeep(strip, rows, tool.threads(), &t)) {
                        e = scenePath + ": cannot render the layers";
                        return false;
                    }
                    transparent += t;
                    samples += (long long)strip.totalSamples();
                    if (rows.ybegin > 0) return true;
                    OIIO::ImageSpec deepSpec = strip.spec;
                    deepSpec.y = 0;
                    deepSpec.height = params.height;
                    deepSpec.channelformats = deepFormats;
                    deepSpec.attribute("dhdr:source", scenePath);
                    stampTime(deepSpec);
                    if (const std::string sha = sceneFingerprint(scenePath); !sha.empty())
                        deepSpec.attribute(gbuffer::kSceneFingerprint, sha);
                    if (file.file().openDeep(deepSpec)) return true;
                    e = file.file().geterror();
                    return false;
                };
                stages.write = [&](OIIO::ROI rows, int, std::string& e) {
                    OIIO::DeepData data;
                    toDeepData(strip, rows.ybegin, rows.yend, data, deepFormats);
                    if (file.file().writeDeepRows(rows.ybegin, rows.yend, data)) return true;
                    e = file.file().geterror();
                    return false;
                };
                const OIIO::ROI frameRows(0, params.width, 0, params.height);
                if (std::string e; !runStrips(frameRows, streaming, stages, e)) {
                    tool.fail(e);
                    return false;
                }
                if (!file.commit()) return false;
                tool.info("deep: " + std::to_string(samples) + " samples, " +
                          std::to_string(transparent) + " partly transparent; " +
                          std::to_string(int(std::chrono::duration<double, std::milli>(
                                                 std::chrono::steady_clock::now() - s0)
                                                 .count() +
                                             0.5)) +
                          " ms");
                if (samples == 0)
                    tool.warn(outPath + ": no surface in view: every pixel is background");
                return writeLightsOut(frame, scene, scenePath);
            }
            tool.info("no partly transparent surface in view: writing a flat G-buffer");
        }
        app::AtomicOutput file(tool, outPath);
        if (!file.open(spec, gbufferChannelFormats(bool(motion)))) return false;
        // Strip by strip: each strip is traced in parallel and written while the next is
        // traced, and memory stays at two strips whatever the image size.
        long long covered = 0;
        StripPipelineParams streaming;
        streaming.rows = kStrip;
        streaming.writeBehind = tool.threads() != 1;
        app::Progress progress(tool, "dhdr-gbuffer: rendering");
        streaming.progress = progress.over();
        StripPipeline pipeline(OIIO::ROI(0, params.width, 0, params.height), streaming);
        pipeline.setOutput(file.file());
        const bool rendered = pipeline.run([&](StripContext& strip) {
            if (!renderer.render(*strip.output, strip.rows, tool.threads())) {
                strip.error = scenePath + ": " + strip.output->geterror();
                return false;
            }
            const auto* px = static_cast<const float*>(strip.output->localpixels());
            const size_t nch = size_t(strip.output->nchannels());
            for (size_t i = 0, n = strip.rows.npixels(); i < n; ++i)
                covered += px[i * nch] > 0.0f;
            return true;
        });
        if (!rendered) {
            tool.fail(pipeline.error());
            return false;
        }
        const double traceMs = pipeline.processMs();
        if (!file.commit()) return false;
        if (covered == 0)
            tool.warn(outPath + ": no surface in view: every pixel is background (check the "
                                "camera, or the scene's geometry)");
        if (!writeLightsOut(frame, scene, scenePath)) return false;
        const auto t2 = std::chrono::steady_clock::now();
        auto ms = [](double v) { return std::to_string(int(v + 0.5)) + " ms"; };
        const double totalMs = std::chrono::duration<double, std::milli>(t2 - t1).count();
        tool.info("load " + ms(std::chrono::duration<double, std::milli>(t1 - t0).count()) +
                  ", trace " + ms(traceMs) + ", write " + ms(totalMs - traceMs));
        return true;
    });
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-gbuffer", [&] { return run(argc, argv); });
}
