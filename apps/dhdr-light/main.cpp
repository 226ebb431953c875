// dhdr-light: a G-buffer and a lights file in, linear HDR radiance out (docs/tools.md).
#include "../common/frames.h"
#include "../common/light_options.h"
#include "../common/param_options.h"
#include "../common/tool.h"
#include "frame_probes.h"
#include "whole_frame.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <dhdr/deferred/denoise/denoise.h>
#include <dhdr/deferred/direct/ambient_occlusion.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_import.h>
#include <dhdr/deferred/geometry/posed_scene.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/io/sanitize.h>
#include <dhdr/io/strip_pipeline.h>
#include <dhdr/io/strip_reader.h>
#include <filesystem>
#include <future>
#include <malloc.h>
#include <memory>
#include <optional>
#include <thread>

using namespace dhdr;

namespace {

int run(int argc, char** argv) {
    app::CommandLine cl(
        "dhdr-light",
        "GBUFFER.exr [--scene SCENE] [--lights LIGHTS.json...] -o FRAME.exr [options]",
        "Deferred lighting: shades every covered pixel of a G-buffer with Lambert diffuse plus\n"
        "Cook-Torrance specular (GGX, height-correlated Smith, Schlick) under point, spot,\n"
        "directional, ambient, sphere and rectangle lights (docs/lights.md), adds emission,\n"
        "and writes linear HDR RGBA. Each light is evaluated only in the tiles its screen\n"
        "rectangle covers. With --scene (the glTF/OBJ file the G-buffer was rendered from),\n"
        "shadow rays make lights cast hard and soft shadows, glowing surfaces light the\n"
        "scene, and --ao rt traces ambient occlusion (docs/lighting.md). Half output clamps\n"
        "radiance past 65504 (and says how many values); --type float keeps it.");
    app::LightOptions lightOptions;
    std::string plateArg, background, dataType = "half", scenePath, aoMode = "off",
                                      envSpecular = "auto", gi = "direct";
    bool bruteForce = false, aovs = false, noShadows = false;
    // The counts' options, ranges and defaults come from the library's table.
    LightingParams params;
    params.aoSamples = 16; // with --ao rt or ssao; 0 when AO is off
    float aoDistance = 1.0f;
    app::addLightOptions(cl, lightOptions);
    cl.option("--scene", scenePath, "FILE",
              "the scene the G-buffer was rendered from: shadows, emissive lights, --ao rt, and "
              "its own lights when no --lights is given; posed at the time and with the "
              "animations an animated G-buffer records (docs/animation.md)");
    bool strict = false;
    cl.flag("--strict", strict,
            "with --scene or --camera-from: a texture the scene names that cannot be read is an "
            "error (default: a warning, and the material shows magenta)");
    cl.flag("--no-shadows", noShadows,
            "with --scene, trace no shadow rays (the unshadowed reference; AO is still traced)");
    app::addParamOptions(cl, params, kLightingParamTable);
    cl.option("--ao", aoMode, "off|rt|ssao",
              "ambient occlusion of the ambient light: rt traces rays in the scene (needs "
              "--scene), ssao works from the G-buffer alone (default off)");
    cl.option("--ao-distance", aoDistance, "D",
              "rt: a hit closer than D occludes; ssao: the kernel's radius; scene units, metres "
              "for glTF (default 1)",
              {0.0, 1e30, true, false});
    cl.option("--background", background, "R,G,B[,A]|env",
              "colour where there is no surface (default: transparent black); env: the "
              "environment light seen by the camera");
    cl.option("--plate", plateArg, "FILE|env",
              "composite the result over a photograph of the frame's size (or the environment "
              "light as the camera sees it): objects and the shadows a --ground-plane catches, "
              "onto the plate; A is then 1");
    std::string denoise = "on";
    cl.option("--env-specular", envSpecular, "auto|split-sum|quadrature",
              "how environments' specular light is integrated: the split sum (prefiltered\n"
              "levels), a 32-sample quadrature of the exact lobe (right at grazing angles on\n"
              "rough surfaces, where the split sum is 10-15 % dark), or auto: the quadrature\n"
              "from roughness 0.3 up (docs/ibl.md; default auto)");
    cl.option("--denoise", denoise, "on|off",
              "filter the environments' shadow rays (--env-samples) and --ao rt over\n"
              "neighbouring pixels of the same surface, guided by the G-buffer's normals,\n"
              "positions and object ids (edge-avoiding a-trous, 32 pixels' reach; flat\n"
              "G-buffers); off: each pixel's unbiased estimate (default on)");
    cl.option("--gi", gi, "direct|path",
              "direct: deferred shading (indirect light from --probes when given); path: the\n"
              "reference, unbiased path tracing from each pixel's first hit (needs --scene;\n"
              "--spp paths a pixel, --path-bounces; no denoiser, probes or AO; slow: use it\n"
              "on a small frame or a crop to check a fast render; docs/gi.md; default direct)");
    cl.flag("--brute-force", bruteForce, "evaluate every light at every pixel (the reference)");
    cl.flag("--aovs", aovs,
            "also write the G-buffer's Z and N.X N.Y N.Z channels (and its motion layer, "
            "motion.X-W, when it has one), AO, the probes' indirect.R/G/B and the specular "
            "indirect light specular.R/G/B");
    cl.option("--type", dataType, "half|float", "pixel type of the output EXR (default half)");
    std::string deepOut, probesPath, channelsArg, cameraFrom;
    cl.option("--channels", channelsArg, "MAP|blender",
              "read another renderer's passes through a channel map (JSON, docs/interop.md); "
              "blender: Cycles' Depth, Position, Normal, Vector and the BaseColor, Roughness, "
              "Metallic AOVs");
    cl.option("--camera-from", cameraFrom, "SCENE[:CAMERA]",
              "with --channels, the camera of the scene file the passes were rendered from "
              "(default its first camera)");
    cl.option("--probes", probesPath, "FILE",
              "light probes baked by dhdr-probes for this scene: indirect diffuse light "
              "(docs/gi.md); with --scene, a ray settles a probe's visibility where its "
              "distance map cannot (at edges); one file for every frame, or a frame pattern "
              "(probes.####.exr, "
              "dhdr-probes --frames): each G-buffer takes its own frame's, and one baked at "
              "another moment than the G-buffer shows is a warning");
    cl.option("--deep-out", deepOut, "FILE",
              "with a deep G-buffer, also write each lit sample as a deep RGBA EXR "
              "(premultiplied, front to back, Z = ZBack) for deep compositing");
    cl.epilog("Examples:\n"
              "  dhdr-light frame.gbuf.exr --lights testdata/cornell_box.lights.json "
              "-o frame.hdr.exr\n"
              "  dhdr-light frame.gbuf.exr --scene testdata/cornell_box.gltf --ao rt "
              "-o frame.hdr.exr");
    // Every file an option reads is an input that no output may overwrite.
    for (const char* option : {"--scene", "--probes"})
        cl.namesFile(option, app::FileRole::Input);
    cl.namesFile("--plate", app::FileRole::Input,
                 [](const std::string& v) { return v == "env" ? std::string() : v; });
    cl.namesFile("--channels", app::FileRole::Input,
                 [](const std::string& v) { return v == "blender" ? std::string() : v; });
    cl.namesFile("--camera-from", app::FileRole::Input, [](const std::string& v) {
        // SCENE[:CAMERA], as read below: the part before the last colon unless the whole
        // value is a file.
        const size_t colon = v.rfind(':');
        return colon == std::string::npos || std::filesystem::exists(v) ? v : v.substr(0, colon);
    });
    cl.namesFile("--deep-out", app::FileRole::Output);
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-light", cl);
    if (cl.inputs().size() != 1) {
        std::fprintf(stderr, "dhdr-light: usage error: give one G-buffer file\n");
        return app::kExitUsage;
    }
    auto usage = [](const std::string& message) {
        std::fprintf(stderr, "dhdr-light: usage error: %s\n", message.c_str());
        return app::kExitUsage;
    };
    const std::vector<std::string>& lightsPaths = lightOptions.files;
    if (lightsPaths.empty() && scenePath.empty())
        return usage("no lights: give --lights FILE, or --scene SCENE for the scene's own");
    if (const std::string problem = app::lightOptionsProblem(lightOptions, !scenePath.empty());
        !problem.empty())
        return usage(problem);
    params.diffuse = app::diffuseModel(lightOptions);
    if (denoise != "on" && denoise != "off") return usage("--denoise takes on or off");
    if (envSpecular == "auto")
        params.environmentSpecular = IblSpecular::Auto;
    else if (envSpecular == "split-sum")
        params.environmentSpecular = IblSpecular::SplitSum;
    else if (envSpecular == "quadrature")
        params.environmentSpecular = IblSpecular::Quadrature;
    else
        return usage("--env-specular must be auto, split-sum or quadrature");
    params.denoise = denoise == "on";
    if (aoMode != "off" && aoMode != "rt" && aoMode != "ssao")
        return usage("--ao must be off, rt or ssao");
    if (gi != "direct" && gi != "path") return usage("--gi must be direct or path");
    params.pathTrace = gi == "path";
    if (!params.pathTrace && (params.pathSamples != LightingParams{}.pathSamples ||
                              params.pathBounces != LightingParams{}.pathBounces))
        return usage("--spp and --path-bounces are for --gi path");
    if (params.pathTrace) {
        if (scenePath.empty()) return usage("--gi path traces the scene: give --scene SCENE");
        if (!probesPath.empty())
            return usage("--gi path computes the indirect light itself: drop --probes");
        if (aoMode != "off") return usage("--gi path has no AO: drop --ao");
        params.denoise = false; // the reference is each pixel's own estimate
    }
    if (scenePath.empty()) {
        if (aoMode == "rt") return usage("--ao rt traces rays in the scene: give --scene SCENE");
        if (noShadows) return usage("--no-shadows needs --scene (without it nothing is shadowed)");
        if (params.environmentSamples != LightingParams{}.environmentSamples)
            return usage("--env-samples traces rays in the scene: give --scene");
        if (params.catcherBounceSamples != LightingParams{}.catcherBounceSamples)
            return usage("--catcher-bounce traces rays in the scene: give --scene");
        if (params.specularSamples != LightingParams{}.specularSamples)
            return usage("--specular-samples traces rays in the scene: give --scene");
    }
    if (dataType != "half" && dataType != "float") {
        std::fprintf(stderr, "dhdr-light: usage error: --type must be half or float\n");
        return app::kExitUsage;
    }
    params.bruteForce = bruteForce;
    params.plateEnvironment = plateArg == "env";
    if (background == "env") {
        params.environmentBackground = true;
    } else if (!background.empty()) {
        std::vector<double> v;
        std::string error;
        if (!app::parseFloatNumbers(background, v, 0, error) || (v.size() != 3 && v.size() != 4)) {
            std::fprintf(stderr, "dhdr-light: usage error: --background%s\n",
                         error.empty() ? " needs 3 or 4 numbers" : (": " + error).c_str());
            return app::kExitUsage;
        }
        for (size_t i = 0; i < 4; ++i)
            params.background[i] = i < v.size() ? float(v[i]) : 1.0f;
    }
    if (aovs) params.passThrough = {"Z", "N.X", "N.Y", "N.Z"};
    params.shadows = !noShadows;
    SsaoParams ssao;
    ssao.samples = params.aoSamples;
    params.aoSamples = aoMode == "rt" ? params.aoSamples : 0;
    params.aoDistance = aoDistance;
    params.writeAO = aovs && aoMode != "off";
    params.writeIndirect = aovs && !probesPath.empty();
    params.writeSpecular = aovs && !scenePath.empty();
    ssao.radius = aoDistance;
    if (aoMode == "ssao")
        if (const std::string e = checkRanges(ssao, kSsaoParamTable); !e.empty())
            return usage(e + " with --ao ssao");
    // The scene: its triangles for shadow and AO rays, its emissive meshes and its lights,
    // posed at each G-buffer's time (its ray caster is built for the first G-buffer).
    const bool withScene = !scenePath.empty();
    PosedScene posed;
    std::string sceneSHA;
    std::vector<Light> sceneLights;
    if (withScene) {
        const auto t = std::chrono::steady_clock::now();
        if (std::string e; !posed.load(scenePath, SceneOptions{strict}, e)) return tool.fail(e);
        const Scene& scene = posed.scene();
        for (const std::string& warning : scene.warnings)
            tool.info(scenePath + ": " + warning);
        sceneSHA = sceneFingerprint(scenePath);
        sceneLights = app::sceneLights(tool, scene, scenePath, lightOptions);
        if (lightsPaths.empty() && sceneLights.empty())
            return tool.fail(scenePath + ": the scene has no lights and no emissive surfaces; " +
                             "give a lights file with --lights");
        tool.info(scenePath + ": " + std::to_string(scene.meshes.size()) + " meshes loaded in " +
                  std::to_string(int(std::chrono::duration<double, std::milli>(
                                         std::chrono::steady_clock::now() - t)
                                         .count())) +
                  " ms" + (noShadows ? "; shadows off (--no-shadows)" : ""));
    } else {
        tool.info("no --scene: lights are not shadowed and emissive surfaces light nothing");
    }
    std::vector<std::string> paths = {cl.inputs()[0]};
    paths.insert(paths.end(), lightsPaths.begin(), lightsPaths.end());
    // Probes with a frame pattern are a frame's input like its G-buffer (the last of them).
    const bool framedProbes = app::FramePattern(probesPath).isSequence();
    if (framedProbes) paths.push_back(probesPath);
    app::FramePlan plan;
    if (const int status = app::planFrames(tool, paths, plan); status >= 0) return status;

    // Lights files without a frame pattern hold the same lights for every frame: read once.
    // A frame's lights are the scene's (as posed for it) and then the files'.
    const bool animatedLights =
        std::any_of(plan.inputs.begin() + 1, plan.inputs.end() - (framedProbes ? 1 : 0),
                    [](const app::FramePattern& p) { return p.isSequence(); });
    std::vector<Light> fileLights;
    if (!animatedLights && !app::addLightsFiles(tool, lightsPaths, lightOptions, fileLights))
        return app::kExitFailure;
    std::vector<Light> lights = sceneLights;
    lights.insert(lights.end(), fileLights.begin(), fileLights.end());
    LightingInputs inputs{lights, nullptr};
    // Another renderer's passes: the channel map, and the camera they were rendered with.
    ChannelMap channelMap;
    if (!channelsArg.empty()) {
        std::string error;
        if (channelsArg == "blender")
            channelMap = blenderChannelMap();
        else if (!readChannelMap(channelsArg, channelMap, error))
            return tool.fail(channelsArg + ": " + error);
        if (!deepOut.empty())
            return usage("--deep-out needs a deep dhdr G-buffer; --channels reads flat passes");
    } else if (!cameraFrom.empty()) {
        return usage("--camera-from goes with --channels");
    }
    std::optional<Camera> foreignCamera;
    if (!cameraFrom.empty()) {
        std::string file = cameraFrom, name;
        if (const size_t colon = cameraFrom.rfind(':');
            colon != std::string::npos && !std::filesystem::exists(cameraFrom)) {
            file = cameraFrom.substr(0, colon);
            name = cameraFrom.substr(colon + 1);
        }
        Scene cameras;
        std::string error;
        if (!loadScene(file, cameras, error, SceneOptions{strict})) return tool.fail(error);
        for (const SceneCamera& c : cameras.cameras)
            if (name.empty() || c.name == name) {
                if (!c.problem.empty())
                    return tool.fail(file + ": camera '" + c.name +
                                     "' cannot be rendered from: " + c.problem);
                foreignCamera = c.camera;
                break;
            }
        if (!foreignCamera)
            return tool.fail(file + ": no camera" + (name.empty() ? "" : " named '" + name + "'"));
    }
    app::FrameProbes probes(probesPath, plan.frames.size());
    if (probes.given()) {
        // One file for every frame is read now; a pattern's files as their frames come.
        if (!framedProbes && !probes.read(tool, probesPath, plan.frames.front(), params.diffuse))
            return app::kExitFailure;
        inputs.probes = &probes.volume();
    }
    OIIO::ImageBuf plate;
    if (!plateArg.empty() && plateArg != "env") {
        plate.reset(plateArg);
        // Its header first: a plate over --max-pixels is refused before its pixels are read.
        if (plate.init_spec(plateArg, 0, 0))
            if (const std::string e =
                    pixelLimitError(plate.spec().width, plate.spec().height, plate.spec().depth);
                !e.empty())
                return tool.fail(plateArg + ": " + e);
        if (!plate.read(0, 0, true, OIIO::TypeDesc::FLOAT))
            return tool.fail(plateArg + ": cannot read the plate: " + plate.geterror());
        inputs.plate = &plate;
    }
    if (plateArg == "env" && std::none_of(lights.begin(), lights.end(), [](const Light& l) {
            return l.type == LightType::Environment;
        }))
        return tool.fail("--plate env: there is no environment light to composite over");
    if (params.environmentBackground &&
        std::none_of(lights.begin(), lights.end(),
                     [](const Light& l) { return l.type == LightType::Environment; }))
        tool.warn("--background env: no environment light; the background stays transparent");

    const app::FramePattern deepOutput(deepOut);
    auto checkScene = [&](const std::string& path, const OIIO::ImageSpec& gspec) {
        if (!withScene) return;
        const std::string recorded = gspec.get_string_attribute(gbuffer::kSceneFingerprint);
        if (recorded.empty())
            tool.info(path + ": the G-buffer does not record its scene; trusting --scene");
        else if (recorded != sceneSHA)
            tool.warn(path + ": rendered from another scene file than " + scenePath +
                      " (its SHA-1 differs): shadows may not match the pixels");
    };
    // What every G-buffer needs before shading, flat, deep or mapped: a camera, a plate of
    // its size placed on its pixels, and a word when --scene is another file.
    auto prepareFrame = [&](const std::string& path, const OIIO::ImageSpec& gspec) {
        std::string error;
        if (gbuffer::CameraInfo camera; !gbuffer::readCamera(gspec, camera, error)) {
            tool.fail(
                path + ": " + error +
                (channelsArg.empty() ? "" : "; give the camera with --camera-from SCENE[:NAME]"));
            return false;
        }
        if (inputs.plate &&
            (plate.spec().width != gspec.width || plate.spec().height != gspec.height)) {
            tool.fail(plateArg + ": the plate is " + std::to_string(plate.spec().width) + "x" +
                      std::to_string(plate.spec().height) + ", the frame " +
                      std::to_string(gspec.width) + "x" + std::to_string(gspec.height));
            return false;
        }
        if (inputs.plate) plate.set_origin(gspec.x, gspec.y);
        checkScene(path, gspec);
        if (probes.given() && !probes.checkMoment(tool, path, gspec)) return false;
        // The scene at the moment the G-buffer shows, and the lights it gives there.
        bool moved = false;
        if (withScene) {
            PoseReport report;
            const bool posedFor = posed.poseFor(path, gspec, report);
            tool.say(report.warnings, report.notes);
            if (!posedFor) return tool.fail(report.error), false;
            moved = report.moved;
            inputs.visibility = posed.caster().get();
            inputs.scene = posed.caster().get();
            if (moved) sceneLights = app::sceneLights(posed.scene(), lightOptions);
        }
        if (moved || animatedLights) {
            lights = sceneLights;
            lights.insert(lights.end(), fileLights.begin(), fileLights.end());
        }
        // --aovs: the motion layer too, where the G-buffer has one (dhdr's, or another
        // renderer's vectors through --channels), so that dhdr-motionblur needs no --gbuffer.
        if (aovs) {
            params.passThrough = {"Z", "N.X", "N.Y", "N.Z"};
            if (std::all_of(std::begin(gbuffer::kMotion), std::end(gbuffer::kMotion),
                            [&](const char* c) { return gspec.channelindex(c) >= 0; }))
                params.passThrough.insert(params.passThrough.end(), std::begin(gbuffer::kMotion),
                                          std::end(gbuffer::kMotion));
        }
        return true;
    };
    auto since = [](auto t) {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t)
            .count();
    };
    const app::WholeFrameRun whole{
        tool, inputs, params, dataType == "half" ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT,
        prepareFrame};
    auto lightFilesOf = [](const std::vector<std::string>& in) {
        std::string files;
        for (size_t i = 1; i < in.size(); ++i)
            files += (i > 1 ? ", " : "") + in[i];
        return files;
    };
    return app::runFrames(tool, plan, [&](int frameNumber, const auto& all, const auto& out) {
        // The G-buffer and the lights files; the frame's probe file apart.
        std::vector<std::string> in = all;
        if (framedProbes) in.pop_back();
        const std::string& path = in[0];
        if (animatedLights) {
            fileLights.clear();
            if (!app::addLightsFiles(tool, {in.begin() + 1, in.end()}, lightOptions, fileLights))
                return false;
        }
        const auto start = std::chrono::steady_clock::now();
        if (!std::filesystem::exists(path)) {
            tool.fail(path + ": no such file");
            return false;
        }
        // This frame's probes, before any output is opened: a missing file fails the frame.
        if (framedProbes && !probes.read(tool, all.back(), frameNumber, params.diffuse))
            return false;
        if (!channelsArg.empty())
            return app::lightMappedPasses(whole, channelMap, foreignCamera, path, out,
                                          lightFilesOf(in));
        // Flat or deep, before any pixel is read or any output opened.
        std::string error;
        int part = 0;
        bool deepInput = false;
        if (!gbuffer::probeGBufferFile(path, part, deepInput, error)) {
            tool.fail(error);
            return false;
        }
        if (deepInput) {
            if (aoMode == "ssao") {
                tool.fail(path + ": --ao ssao works on flat G-buffers; a deep one needs --ao rt");
                return false;
            }
            return app::lightDeepGBuffer(whole, path, part, out, lightFilesOf(in),
                                         deepOut.empty() ? "" : deepOutput.path(frameNumber));
        }
        if (!deepOut.empty()) {
            tool.fail(path + ": --deep-out needs a deep G-buffer (dhdr-gbuffer --deep); this one "
                             "is flat");
            return false;
        }
        StripReader reader;
        if (!reader.open(path, part, 0, 1 << 20, tool.threads(), error)) {
            tool.fail(cannotRead(path, error));
            return false;
        }
        const OIIO::ImageSpec& gspec = reader.spec();
        gbuffer::Layout layout;
        std::string missing;
        if (!gbuffer::findLayout(gspec, layout, missing)) {
            tool.fail(path + ": no channel '" + missing + "' — is this a G-buffer?");
            return false;
        }
        if (!prepareFrame(path, gspec)) return false;
        // Strip by strip, whole rows of tiles at a time: memory stays at one strip of the
        // G-buffer and one of the output whatever the frame's size, and each pixel's result
        // is the same as from the whole frame (tiles are laid over the frame).
        LightingParams strips = params;
        strips.frame = OIIO::get_roi(gspec);
        // SSAO looks at neighbouring pixels anywhere in the frame: one strip, the whole frame.
        // The denoiser reads kDenoiseReach rows around each pixel: each strip is read with
        // that halo, and taller, so that filtering the halo again is a smaller share (its rays
        // are traced once: EstimateCarry). Without a scene no ray is traced: nothing to filter.
        const bool halo = params.denoise && withScene &&
                          (params.environmentSamples > 0 || params.aoSamples > 0 ||
                           params.catcherBounceSamples > 0 || params.specularSamples > 0);
        // About 256 rows (128 without a halo), as equal as whole rows of tiles allow: a last
        // strip of a few rows would filter two halos for little (1080 rows: 4 strips of 272
        // rather than 256 × 4 and 56). 512 rows took as long at 1080p, in 1.46× the memory
        // (bench/README.md, session 18).
        const int target = halo ? 256 : 128;
        const int count = std::max(1, (gspec.height + target * 9 / 8 - 1) / (target * 9 / 8));
        const int each = (gspec.height + count - 1) / count;
        const int rows =
            aoMode == "ssao"
                ? gspec.height
                : params.tileSize * std::max(1, (each + params.tileSize - 1) / params.tileSize);
        std::string lightFiles;
        for (size_t i = 1; i < in.size(); ++i)
            lightFiles += (i > 1 ? ", " : "") + in[i];
        app::AtomicOutput file(tool, out);
        LightingStats stats;
        app::Progress progress(tool, "dhdr-light: " + path);
        // The next strip is read on another thread while this one is shaded and written:
        // decoding the G-buffer is most of the work.
        StripPipelineParams streaming;
        streaming.rows = rows;
        // An environment's specular light reads the next row's normals (the pixel's
        // footprint, lighting.h): one row at least.
        const bool environment = std::any_of(lights.begin(), lights.end(), [](const Light& l) {
            return l.type == LightType::Environment;
        });
        streaming.halo = aoMode == "ssao" ? 0
                         : halo           ? kDenoiseReach
                                          : (environment ? kFootprintReach : 0);
        streaming.nthreads = tool.threads();
        streaming.progress = progress.over();
        // The strips' shared rows are decoded once (the shading only reads its G-buffer).
        streaming.shareHalo = true;
        StripPipeline pipeline(OIIO::get_roi(gspec), streaming);
        // Z is +∞ on the background by contract; every other channel must be finite.
        StripInput gbufferRows{[&](int y0, int y1, OIIO::ImageBuf& s, std::string& e) {
                                   return reader.read(y0, y1, s, e);
                               },
                               path,
                               {{0, layout.depth}, {layout.depth + 1, gspec.nchannels}}};
        gbufferRows.readReusing = [&](int y0, int y1, const OIIO::ImageBuf& previous,
                                      OIIO::ImageBuf& s, int& copiedEnd, std::string& e) {
            return reader.read(y0, y1, s, e, &previous, &copiedEnd);
        };
        pipeline.addInput(std::move(gbufferRows));
        const OIIO::TypeDesc type =
            dataType == "half" ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT;
        pipeline.setOutput(file.file(), [&](const OIIO::ImageBuf& first, std::string& e) {
            if (file.file().open(app::litFrameSpec(first.spec(), gspec, lightFiles), {type}))
                return true;
            e = file.file().geterror();
            return false;
        });
        OIIO::ImageBuf ao;
        // The estimates of the rows two strips share are traced once, by the upper strip.
        EstimateCarry carry;
        const bool lit = pipeline.run([&](StripContext& strip) {
            const OIIO::ImageBuf& gbuf = *strip.inputs[0];
            LightingInputs stripInputs = inputs;
            stripInputs.carry = &carry;
            if (aoMode == "ssao") {
                if (!screenSpaceAO(ao, gbuf, ssao, tool.threads())) {
                    strip.error = path + ": " + ao.geterror();
                    return false;
                }
                stripInputs.ambientOcclusion = &ao;
            }
            LightingStats rowStats;
            const OIIO::ROI own(gspec.x, gspec.x + gspec.width, strip.rows.ybegin, strip.rows.yend);
            if (!shadeGBuffer(*strip.output, gbuf, stripInputs, strips, own, tool.threads(),
                              &rowStats)) {
                strip.error = path + ": " + strip.output->geterror();
                return false;
            }
            stats += rowStats;
            return true;
        });
        if (!lit) {
            tool.fail(pipeline.error());
            return false;
        }
        const NonFiniteCount replaced = pipeline.replaced()[0];
        const double readMs = pipeline.readMs(), shadeMs = pipeline.processMs(),
                     writeMs = pipeline.writeMs();
        if (!file.commit()) return false;
        tool.reportNonFinite(path, replaced, false);
        if (stats.coveredPixels == 0)
            tool.warn(path + ": no surface in view: A is 0 everywhere (an empty frame)");

        auto ms = [](double v) { return std::to_string(int(v + 0.5)) + " ms"; };
        const double pixels = double(std::max<long long>(stats.coveredPixels, 1));
        char line[200];
        std::snprintf(line, sizeof line,
                      "%zu lights; %lld covered pixels; per covered pixel %.2f considered, %.2f "
                      "within range%s; %lld tile-list entries",
                      lights.size(), stats.coveredPixels, double(stats.lightEvaluations) / pixels,
                      double(stats.lightsReaching) / pixels, bruteForce ? " (brute force)" : "",
                      stats.tileListEntries);
        tool.info(line);
        const long long traced = stats.shadowRays + stats.aoRays + stats.bounceRays +
                                 stats.pathRays + stats.specularRays;
        if (traced > 0) {
            const double seconds = std::max(shadeMs, 1e-3) / 1000.0;
            std::snprintf(
                line, sizeof line,
                "%lld shadow rays (%.2f per covered pixel), %lld AO rays, %lld catcher bounce "
                "rays, %lld specular rays, %lld path rays; %.2f M rays/s per thread over the "
                "shading time",
                stats.shadowRays, double(stats.shadowRays) / pixels, stats.aoRays, stats.bounceRays,
                stats.specularRays, stats.pathRays,
                double(traced) / seconds / 1e6 /
                    double(tool.threads() > 0 ? tool.threads()
                                              : int(std::thread::hardware_concurrency())));
            tool.info(line);
        }
        tool.info("total " + ms(since(start)) + ": read " + ms(readMs) + ", shade " + ms(shadeMs) +
                  ", write " + ms(writeMs) +
                  (reader.streamed() ? "" : " (read whole: not a scanline EXR)"));
        return true;
    });
}

} // namespace

int main(int argc, char** argv) {
#if defined(M_MMAP_THRESHOLD) && defined(M_TRIM_THRESHOLD)
    // Every strip allocates and frees the same buffers (the denoiser's planes alone, about
    // 140 MB a strip at 1080p): glibc keeps them for the next strip instead of returning them
    // to the kernel and taking page faults again, about a tenth of the denoiser's time
    // (bench/README.md, session 19). The peak stays that of one strip.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
    return app::guardedMain("dhdr-light", [&] { return run(argc, argv); });
}
