// dhdr-light: a G-buffer and a lights file in, linear HDR radiance out (docs/tools.md).
#include "../common/frames.h"
#include "../common/light_options.h"
#include "../common/param_options.h"
#include "../common/tool.h"
#include "baked_probes.h"
#include "flat_frame.h"
#include "frame_probes.h"
#include "whole_frame.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_import.h>
#include <dhdr/deferred/geometry/posed_scene.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/integrator/lighting_options.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/io/pixel_limit.h>
#include <filesystem>
#include <malloc.h>
#include <optional>

using namespace dhdr;

namespace {

// Whether the G-buffer `path` (header `gspec`) records `sha` (--scene's SHA-1) as its scene's:
// a warning when it records another, or one that tells nothing (no SHA-1, or that of no bytes).
void checkFingerprint(const app::Tool& tool, const std::string& path, const OIIO::ImageSpec& gspec,
                      const std::string& scenePath, const std::string& sha) {
    // SHA-1 of zero bytes: what a scene file that was empty or could not be read would record.
    static const std::string kNoBytes = "da39a3ee5e6b4b0d3255bfef95601890afd80709";
    const std::string recorded = gspec.get_string_attribute(gbuffer::kSceneFingerprint);
    std::string lower = recorded;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    const std::string cannotTell =
        ": cannot tell whether it was rendered from " + scenePath + "; trusting --scene";
    if (!gspec.find_attribute(gbuffer::kSceneFingerprint))
        tool.info(path + ": the G-buffer does not record its scene; trusting --scene");
    else if (lower.size() != 40 || lower.find_first_not_of("0123456789abcdef") != std::string::npos)
        tool.warn(path + ": its " + gbuffer::kSceneFingerprint + " '" + recorded +
                  "' is not a SHA-1 (40 hex digits)" + cannotTell);
    else if (lower == kNoBytes)
        tool.warn(path + ": its " + gbuffer::kSceneFingerprint +
                  " is the SHA-1 of no bytes (an empty or unreadable scene file)" + cannotTell);
    else if (recorded != sha)
        tool.warn(path + ": rendered from another scene file than " + scenePath +
                  " (its SHA-1 differs): shadows may not match the pixels");
}

// What the command line asks for.
struct Settings {
    app::LightOptions lights;
    LightingOptions lighting; // the lighting choices: the library's tables
    std::string plate, background, dataType = "half", scenePath, deepOut, probesPath, channels,
                                   cameraFrom;
    bool strict = false;
};

void declareOptions(app::CommandLine& cl, Settings& s) {
    app::addLightOptions(cl, s.lights);
    cl.option("--scene", s.scenePath, "FILE",
              "the scene the G-buffer was rendered from: shadows, emissive lights, --ao rt, and "
              "its own lights when no --lights is given; posed at the time and with the "
              "animations an animated G-buffer records (docs/animation.md)");
    cl.flag("--strict", s.strict,
            "with --scene or --camera-from: a texture the scene names that cannot be read is an "
            "error (default: a warning, and the material shows magenta)");
    app::addParamOptions(cl, s.lighting, kLightingFlagTable);
    app::addParamOptions(cl, s.lighting.params, kLightingParamTable);
    app::addParamOptions(cl, s.lighting, kLightingChoiceTable);
    app::addParamOptions(cl, s.lighting, kLightingFloatTable);
    cl.option("--background", s.background, "R,G,B[,A]|env",
              "colour where there is no surface (default: transparent black); env: the "
              "environment light seen by the camera");
    cl.option("--plate", s.plate, "FILE|env",
              "composite the result over a photograph of the frame's size (or the environment "
              "light as the camera sees it): objects and the shadows a --ground-plane catches, "
              "onto the plate; A is then 1");
    cl.option("--type", s.dataType, "half|float", "pixel type of the output EXR");
    cl.option("--channels", s.channels, "MAP|blender",
              "read another renderer's passes through a channel map (JSON, docs/interop.md); "
              "blender: Cycles' Depth, Position, Normal, Vector and the BaseColor, Roughness, "
              "Metallic AOVs");
    cl.option("--camera-from", s.cameraFrom, "SCENE[:CAMERA]",
              "with --channels, the camera of the scene file the passes were rendered from "
              "(default its first camera)");
    cl.option("--probes", s.probesPath, "FILE",
              "light probes baked by dhdr-probes for this scene: indirect diffuse light "
              "(docs/gi.md); with --scene, a ray settles a probe's visibility where its "
              "distance map cannot (at edges); one file for every frame, or a frame pattern "
              "(probes.####.exr, dhdr-probes --frames): each G-buffer takes its own frame's, "
              "and one baked at another moment than the G-buffer shows is a warning");
    cl.option("--deep-out", s.deepOut, "FILE",
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
}

int usage(const std::string& message) {
    std::fprintf(stderr, "dhdr-light: usage error: %s\n", message.c_str());
    return app::kExitUsage;
}

// The settings as the lighting pass's parameters (the library's rules, resolveLighting) and
// the tool's own checks; -1 to go on, else the exit status.
int resolveSettings(const app::CommandLine& cl, Settings& s, LightingParams& params,
                    SsaoParams& ssao) {
    if (cl.inputs().size() != 1) return usage("give one G-buffer file");
    if (s.background == "env") s.lighting.environmentBackground = true;
    s.lighting.plateEnvironment = s.plate == "env";
    s.lighting.params.diffuse = app::diffuseModel(s.lights);
    const LightingContext context{!s.lights.files.empty(), !s.scenePath.empty(),
                                  !s.probesPath.empty()};
    std::string error;
    if (!resolveLighting(s.lighting, context, Spelling::Option, params, ssao, error))
        return usage(error);
    if (const std::string problem = app::lightOptionsProblem(s.lights, context.scene);
        !problem.empty())
        return usage(problem);
    if (s.dataType != "half" && s.dataType != "float") return usage("--type must be half or float");
    if (!s.background.empty() && s.background != "env") {
        std::vector<double> v;
        if (!app::parseFloatNumbers(s.background, v, 0, error) || (v.size() != 3 && v.size() != 4))
            return usage("--background" +
                         (error.empty() ? std::string(" needs 3 or 4 numbers") : ": " + error));
        for (size_t i = 0; i < 4; ++i)
            params.background[i] = i < v.size() ? float(v[i]) : 1.0f;
    }
    if (!s.channels.empty() && !s.deepOut.empty())
        return usage("--deep-out needs a deep dhdr G-buffer; --channels reads flat passes");
    if (s.channels.empty() && !s.cameraFrom.empty())
        return usage("--camera-from goes with --channels");
    return -1;
}

// A run over the frames: the scene posed for each G-buffer, the lights it and the files give,
// the probes, the plate, and what other renderers' passes need.
class LightRun {
public:
    LightRun(const app::Tool& tool, const Settings& s, LightingParams& params,
             const SsaoParams& ssao)
        : m_tool(tool), m_s(s), m_params(params), m_ssao(ssao), m_probes(s.probesPath, 1) {}

    int setUp(const std::vector<std::string>& inputs);
    bool frame(int frameNumber, const std::vector<std::string>& all, const std::string& out);

private:
    bool loadScene();
    bool readInputs();
    bool readForeignCamera();
    bool prepareFrame(const std::string& path, const OIIO::ImageSpec& gspec);
    bool poseFor(const std::string& path, const OIIO::ImageSpec& gspec);
    bool bakeProbesFor(bool moved);
    bool failed(const std::string& message) const {
        m_tool.fail(message);
        return false;
    }
    app::WholeFrameRun whole() {
        return {
            m_tool, m_inputs, m_params,
            m_s.dataType == "half" ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT,
            [this](const std::string& p, const OIIO::ImageSpec& g) { return prepareFrame(p, g); }};
    }

    const app::Tool& m_tool;
    const Settings& m_s;
    LightingParams& m_params;
    const SsaoParams& m_ssao;
    PosedScene m_posed;
    std::string m_sceneSHA;
    std::vector<Light> m_sceneLights, m_fileLights, m_lights;
    LightingInputs m_inputs{m_lights, nullptr};
    app::FramePlan m_plan;
    bool m_framedProbes = false, m_animatedLights = false;
    app::FrameProbes m_probes;
    app::BakedProbes m_baked; // --gi auto's
    std::string m_probeNote;  // planProbes' last note, said once
    OIIO::ImageBuf m_plate;
    ChannelMap m_channelMap;
    std::optional<Camera> m_foreignCamera;
};

// The scene: its triangles for shadow and AO rays, its emissive meshes and its lights, posed at
// each G-buffer's time (its ray caster is built for the first G-buffer).
bool LightRun::loadScene() {
    const std::string& path = m_s.scenePath;
    if (path.empty()) {
        m_tool.info("no --scene: lights are not shadowed and emissive surfaces light nothing");
        return true;
    }
    const auto t = std::chrono::steady_clock::now();
    if (std::string e; !m_posed.load(path, SceneOptions{m_s.strict}, e)) return failed(e);
    const Scene& scene = m_posed.scene();
    for (const std::string& warning : scene.warnings)
        m_tool.info(path + ": " + warning);
    m_sceneSHA = sceneFingerprint(path);
    m_sceneLights = app::sceneLights(m_tool, scene, path, m_s.lights);
    if (m_s.lights.files.empty() && m_sceneLights.empty()) {
        m_tool.fail(path + ": the scene has no lights and no emissive surfaces; " +
                    "give a lights file with --lights");
        return false;
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
    m_tool.info(path + ": " + std::to_string(scene.meshes.size()) + " meshes loaded in " +
                std::to_string(int(ms)) + " ms" +
                (m_params.shadows ? "" : "; shadows off (--no-shadows)"));
    return true;
}

int LightRun::setUp(const std::vector<std::string>& inputs) {
    if (!loadScene()) return app::kExitFailure;
    std::vector<std::string> paths = inputs;
    paths.insert(paths.end(), m_s.lights.files.begin(), m_s.lights.files.end());
    // Probes with a frame pattern are a frame's input like its G-buffer (the last of them).
    m_framedProbes = app::FramePattern(m_s.probesPath).isSequence();
    if (m_framedProbes) paths.push_back(m_s.probesPath);
    if (const int status = app::planFrames(m_tool, paths, m_plan); status >= 0) return status;
    // Lights files without a frame pattern hold the same lights for every frame: read once.
    // A frame's lights are the scene's (as posed for it) and then the files'.
    m_animatedLights =
        std::any_of(m_plan.inputs.begin() + 1, m_plan.inputs.end() - (m_framedProbes ? 1 : 0),
                    [](const app::FramePattern& p) { return p.isSequence(); });
    if (!m_animatedLights &&
        !app::addLightsFiles(m_tool, m_s.lights.files, m_s.lights, m_fileLights))
        return app::kExitFailure;
    m_lights = m_sceneLights;
    m_lights.insert(m_lights.end(), m_fileLights.begin(), m_fileLights.end());
    if (!readInputs()) return app::kExitFailure;
    if (m_s.plate == "env" && std::none_of(m_lights.begin(), m_lights.end(), isEnvironment))
        return m_tool.fail("--plate env: there is no environment light to composite over");
    if (m_params.environmentBackground &&
        std::none_of(m_lights.begin(), m_lights.end(), isEnvironment))
        m_tool.warn("--background env: no environment light; the background stays transparent");
    return app::runFrames(m_tool, m_plan, [this](int n, const auto& all, const auto& out) {
        return frame(n, all, out);
    });
}

// The channel map and camera of another renderer's passes, the probes and the plate.
bool LightRun::readInputs() {
    std::string error;
    if (m_s.channels == "blender")
        m_channelMap = blenderChannelMap();
    else if (!m_s.channels.empty() && !readChannelMap(m_s.channels, m_channelMap, error))
        return m_tool.fail(m_s.channels + ": " + error);
    if (!m_s.cameraFrom.empty() && !readForeignCamera()) return false;
    m_probes = app::FrameProbes(m_s.probesPath, m_plan.frames.size());
    if (m_probes.given()) {
        // One file for every frame is read now; a pattern's files as their frames come.
        if (!m_framedProbes &&
            !m_probes.read(m_tool, m_s.probesPath, m_plan.frames.front(), m_params.diffuse))
            return false;
        m_inputs.probes = &m_probes.volume();
    }
    if (m_s.plate.empty() || m_s.plate == "env") return true;
    m_plate.reset(m_s.plate);
    // Its header first: a plate over --max-pixels is refused before its pixels are read.
    if (m_plate.init_spec(m_s.plate, 0, 0))
        if (const std::string e =
                pixelLimitError(m_plate.spec().width, m_plate.spec().height, m_plate.spec().depth);
            !e.empty())
            return failed(m_s.plate + ": " + e);
    if (!m_plate.read(0, 0, true, OIIO::TypeDesc::FLOAT))
        return failed(m_s.plate + ": cannot read the plate: " + m_plate.geterror());
    m_inputs.plate = &m_plate;
    return true;
}

// --camera-from SCENE[:CAMERA].
bool LightRun::readForeignCamera() {
    const std::string& from = m_s.cameraFrom;
    std::string file = from, name;
    if (const size_t colon = from.rfind(':');
        colon != std::string::npos && !std::filesystem::exists(from)) {
        file = from.substr(0, colon);
        name = from.substr(colon + 1);
    }
    Scene cameras;
    std::string error;
    if (!dhdr::loadScene(file, cameras, error, SceneOptions{m_s.strict})) return failed(error);
    for (const SceneCamera& c : cameras.cameras)
        if (name.empty() || c.name == name) {
            if (!c.problem.empty())
                return failed(file + ": camera '" + c.name +
                              "' cannot be rendered from: " + c.problem);
            m_foreignCamera = c.camera;
            return true;
        }
    return failed(file + ": no camera" + (name.empty() ? "" : " named '" + name + "'"));
}

// The scene at the moment the G-buffer shows, and the lights it gives there.
bool LightRun::poseFor(const std::string& path, const OIIO::ImageSpec& gspec) {
    bool moved = false;
    if (!m_s.scenePath.empty()) checkFingerprint(m_tool, path, gspec, m_s.scenePath, m_sceneSHA);
    if (m_probes.given() && !m_probes.checkMoment(m_tool, path, gspec)) return false;
    if (!m_s.scenePath.empty()) {
        PoseReport report;
        const bool posedFor = m_posed.poseFor(path, gspec, report);
        m_tool.say(report.warnings, report.notes);
        if (!posedFor) return failed(report.error);
        moved = report.moved;
        m_inputs.visibility = m_posed.caster().get();
        m_inputs.scene = m_posed.caster().get();
        if (moved) m_sceneLights = app::sceneLights(m_posed.scene(), m_s.lights);
    }
    if (moved || m_animatedLights) {
        m_lights = m_sceneLights;
        m_lights.insert(m_lights.end(), m_fileLights.begin(), m_fileLights.end());
    }
    return bakeProbesFor(moved || m_animatedLights);
}

// --gi auto: probes baked for this frame where they help (planProbes), again when the scene
// or the lights have moved since the last bake.
bool LightRun::bakeProbesFor(bool moved) {
    const LightingContext context{!m_s.lights.files.empty(), !m_s.scenePath.empty(),
                                  !m_s.probesPath.empty()};
    const bool catcher = !m_s.scenePath.empty() && m_posed.scene().hasGroundPlane;
    const ProbePlan plan = planProbes(m_s.lighting, context, m_lights, catcher, Spelling::Option);
    if (plan.note != m_probeNote && !plan.note.empty()) m_tool.info(plan.note);
    m_probeNote = plan.note;
    if (plan.source != ProbeSource::Bake) {
        if (!m_probes.given()) m_inputs.probes = nullptr;
        return true;
    }
    m_inputs.probes = m_baked.forFrame(m_tool, m_posed, m_lights, m_s.lights.emissive != "off",
                                       m_params.diffuse, moved);
    m_params.writeIndirect = m_s.lighting.aovs && m_inputs.probes;
    return true;
}

// What every G-buffer needs before shading, flat, deep or mapped: a camera, a plate of its
// size placed on its pixels, a word when --scene is another file, and the scene posed.
bool LightRun::prepareFrame(const std::string& path, const OIIO::ImageSpec& gspec) {
    std::string error;
    // The header is copied into the output: a malformed moment (NaN) is refused here, with or
    // without --scene, rather than written on.
    if (std::optional<gbuffer::Moment> moment; !gbuffer::readMoment(gspec, moment, error))
        return failed(path + ": " + error);
    if (gbuffer::CameraInfo camera; !gbuffer::readCamera(gspec, camera, error)) {
        m_tool.fail(
            path + ": " + error +
            (m_s.channels.empty() ? "" : "; give the camera with --camera-from SCENE[:NAME]"));
        return false;
    }
    if (m_inputs.plate &&
        (m_plate.spec().width != gspec.width || m_plate.spec().height != gspec.height)) {
        m_tool.fail(m_s.plate + ": the plate is " + std::to_string(m_plate.spec().width) + "x" +
                    std::to_string(m_plate.spec().height) + ", the frame " +
                    std::to_string(gspec.width) + "x" + std::to_string(gspec.height));
        return false;
    }
    if (m_inputs.plate) m_plate.set_origin(gspec.x, gspec.y);
    if (!poseFor(path, gspec)) return false;
    // --aovs: the motion layer too, where the G-buffer has one (dhdr's, or another renderer's
    // vectors through --channels), so that dhdr-motionblur needs no --gbuffer.
    if (m_s.lighting.aovs) {
        m_params.passThrough = {"Z", "N.X", "N.Y", "N.Z"};
        if (std::all_of(std::begin(gbuffer::kMotion), std::end(gbuffer::kMotion),
                        [&](const char* c) { return gspec.channelindex(c) >= 0; }))
            m_params.passThrough.insert(m_params.passThrough.end(), std::begin(gbuffer::kMotion),
                                        std::end(gbuffer::kMotion));
    }
    return true;
}

// One frame: `all` holds its G-buffer, its lights files and (a pattern's) probe file.
bool LightRun::frame(int frameNumber, const std::vector<std::string>& all, const std::string& out) {
    std::vector<std::string> in = all;
    if (m_framedProbes) in.pop_back();
    const std::string& path = in[0];
    if (m_animatedLights) {
        m_fileLights.clear();
        if (!app::addLightsFiles(m_tool, {in.begin() + 1, in.end()}, m_s.lights, m_fileLights))
            return false;
    }
    if (!std::filesystem::exists(path)) {
        m_tool.fail(path + ": no such file");
        return false;
    }
    // This frame's probes, before any output is opened: a missing file fails the frame.
    if (m_framedProbes && !m_probes.read(m_tool, all.back(), frameNumber, m_params.diffuse))
        return false;
    std::string lightFiles;
    for (size_t i = 1; i < in.size(); ++i)
        lightFiles += (i > 1 ? ", " : "") + in[i];
    if (!m_s.channels.empty())
        return app::lightMappedPasses(whole(), m_channelMap, m_foreignCamera, path, out,
                                      lightFiles);
    // Flat or deep, before any pixel is read or any output opened.
    std::string error;
    int part = 0;
    bool deepInput = false;
    if (!gbuffer::probeGBufferFile(path, part, deepInput, error)) {
        m_tool.fail(error);
        return false;
    }
    const bool ssao = m_s.lighting.ao == AoMode::ScreenSpace;
    if (deepInput) {
        if (const std::string problem = deepGBufferProblem(m_s.lighting, Spelling::Option);
            !problem.empty())
            return failed(path + ": " + problem);
        const app::FramePattern deepOutput(m_s.deepOut);
        return app::lightDeepGBuffer(whole(), path, part, out, lightFiles,
                                     m_s.deepOut.empty() ? "" : deepOutput.path(frameNumber));
    }
    if (!m_s.deepOut.empty()) {
        m_tool.fail(path + ": --deep-out needs a deep G-buffer (dhdr-gbuffer --deep); this one "
                           "is flat");
        return false;
    }
    return app::lightFlatGBuffer(whole(), ssao ? &m_ssao : nullptr, path, part, out, lightFiles);
}

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
    Settings settings;
    declareOptions(cl, settings);
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-light", cl);
    LightingParams params;
    SsaoParams ssao;
    if (const int status = resolveSettings(cl, settings, params, ssao); status >= 0) return status;
    LightRun lightRun(tool, settings, params, ssao);
    return lightRun.setUp({cl.inputs()[0]});
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
