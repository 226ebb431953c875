// dhdr-gbuffer: a scene in, a multi-channel EXR G-buffer out (docs/tools.md).
#include "../common/frame_timing.h"
#include "../common/frames.h"
#include "../common/param_options.h"
#include "../common/tool.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_depth.h>
#include <dhdr/deferred/gbuffer/gbuffer_stamp.h>
#include <dhdr/deferred/geometry/posed_scene.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/animation.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_camera.h>
#include <dhdr/deferred/scene/scene_info.h>
#include <dhdr/io/strip_pipeline.h>
#include <glm/gtc/constants.hpp>
#include <optional>

using namespace dhdr;

namespace {

// Rows traced and written at a time.
constexpr int kStrip = 64;
// A flat G-buffer's compression unless --compression names one: ZIP at zlib's level 1,
// lossless like every level, which compresses a 1080p frame in about 0.8 of the CPU time of
// OpenEXR's default level for 3-10 % more bytes (docs/gbuffer.md, bench/gbuffer_write.py).
constexpr const char* kDefaultCompression = "zip:1";
// The strips the search for transparent surfaces traced are kept while they fit, so that a
// frame of ordinary size is traced once.
constexpr size_t kKeptBytes = size_t(256) << 20;

// What the command line says.
struct Options {
    std::string size = "1920x1080", cameraName, lookat, lightsOut;
    bool frameAll = false, info = false, groundPlane = false, deep = false, flat = false;
    bool strict = false;
    GBufferParams limits; // --max-layers, --texture-filter (kGBufferParamTable, ...ChoiceTable)
    CameraChoice camera;  // --fov (kCameraFloatTable)
    std::optional<double> groundY;
    app::FrameTiming timing;
};

void declareOptions(app::CommandLine& cl, Options& o) {
    cl.option("--size", o.size, "WxH", "image size in pixels");
    cl.option("--camera", o.cameraName, "NAME", "the scene camera to use (default: the first)");
    cl.option("--lookat", o.lookat, "EX,EY,EZ,TX,TY,TZ[,UX,UY,UZ]",
              "a camera at E looking at T (up U, default 0,1,0) instead of the scene's");
    app::addParamOptions(cl, o.camera, kCameraFloatTable);
    cl.option("--lights-out", o.lightsOut, "FILE",
              "also write the scene's punctual lights as a lights file (docs/lights.md)");
    cl.flag("--deep", o.deep,
            "always write a deep EXR: per pixel every surface up to the first opaque one "
            "(default: only when some pixel holds a partly transparent surface or, with "
            "--pixel-samples, several rays)");
    cl.flag("--flat", o.flat,
            "never write a deep EXR: each pixel's first surface, transparent or not");
    app::addParamOptions(cl, o.limits, kGBufferParamTable);
    app::addParamOptions(cl, o.limits, kGBufferChoiceTable);
    app::addParamOptions(cl, o.limits, kGBufferFloatTable);
    cl.flagWithNumber("--ground-plane", o.groundPlane, o.groundY, "Y",
                      "add an infinite horizontal plane at height Y (default: the scene's lowest "
                      "point) that dhdr-light treats as a shadow catcher for compositing "
                      "(docs/ibl.md)",
                      {-1e30, 1e30});
    cl.flag("--frame-all", o.frameAll,
            "move the camera (the scene's, --lookat's, or without either one looking from the "
            "front and a little above) back until the whole scene fits the image (an error when "
            "no float camera can: coordinates near 3e38)");
    cl.flag("--strict", o.strict,
            "a texture the scene names that cannot be read is an error (default: a warning, and "
            "the material shows magenta (1, 0, 1) times its factor, as in Blender)");
    o.timing.declare(cl);
    cl.flag(
        "--info", o.info,
        "print what the scene holds (bounds, cameras, lights, materials, animations, what is left "
        "out) and exit; needs no -o");
    cl.framesHelp("render frames A to B of the scene's animation (frame N at time N / fps), "
                  "frame N into the output's frame pattern (-o out.####.exr)");
    cl.epilog(
        "Example:\n  dhdr-gbuffer testdata/cornell_box.gltf --size 1280x720 -o frame.gbuf.exr");
    cl.namesFile("--lights-out", app::FileRole::Output);
}

// Prints a usage error; returns its exit status.
int usage(const std::string& message) {
    std::fprintf(stderr, "dhdr-gbuffer: usage error: %s\n", message.c_str());
    return app::kExitUsage;
}

// --size, --max-layers and --texture-filter into `params`. Returns -1 to go on, else the exit
// status.
int parseImage(const Options& o, GBufferParams& params) {
    if (o.deep && o.flat) return usage("--deep and --flat exclude each other");
    params.maxLayers = o.limits.maxLayers;
    params.textureFilter = o.limits.textureFilter;
    params.samples = o.limits.samples;
    params.allPixels = o.limits.allPixels;
    params.pixelFilter = o.limits.pixelFilter;
    params.filterWidth = o.limits.filterWidth;
    if (const std::string e = samplesError(params.samples); !e.empty()) return usage(e);
    if (o.flat && params.samples > 1)
        return usage("--flat holds one ray a pixel; --pixel-samples " +
                     std::to_string(params.samples) +
                     " needs the deep format (give --pixel-samples 1 with --flat)");
    if (!app::parseSize(o.size, params.width, params.height))
        return usage("--size '" + o.size + "' is not WxH");
    if (const std::string e = pixelLimitError(params.width, params.height); !e.empty())
        return usage("--size " + o.size + ": " + e);
    return -1;
}

// --lookat's camera (none without it). Returns -1 to go on, else the exit status.
int parseLookat(const std::string& lookat, std::optional<Camera>& camera) {
    if (lookat.empty()) return -1;
    std::vector<double> v;
    std::string error;
    if (!app::parseFloatNumbers(lookat, v, 0, error) || (v.size() != 6 && v.size() != 9)) {
        // The camera's rays are traced in float (Embree).
        return usage(error.empty() ? "--lookat needs 6 or 9 numbers" : "--lookat: " + error);
    }
    const glm::dvec3 up = v.size() == 9 ? glm::dvec3(v[6], v[7], v[8]) : glm::dvec3(0, 1, 0);
    const glm::dvec3 eye(v[0], v[1], v[2]), target(v[3], v[4], v[5]);
    if (glm::length(target - eye) < 1e-9 * std::max(1.0, glm::length(eye)))
        return usage("--lookat: the eye and the target are the same point");
    if (glm::length(up) == 0.0) return usage("--lookat: the up vector is zero");
    camera = Camera::lookAt({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, up, glm::radians(39.6));
    return -1;
}

// The frames of a run: the scene loaded once for all frames that name the same file and, when
// animated, posed at each frame's time; each frame traced and written flat or deep.
class GBufferFrames {
public:
    // `stillFrames`: how many frames render one scene file (the run's, unless the scene's
    // path is a frame pattern), all alike when the scene does not move.
    GBufferFrames(const app::Tool& tool, const Options& o, const GBufferParams& params,
                  std::optional<Camera> lookat, size_t stillFrames)
        : m_tool(tool), m_o(o), m_params(params), m_lookat(std::move(lookat)),
          m_lightsOutput(o.lightsOut), m_depth(o.deep   ? GBufferDepth::Deep
                                               : o.flat ? GBufferDepth::Flat
                                                        : GBufferDepth::Auto),
          m_stillFrames(stillFrames) {}

    bool frame(int frame, const std::string& scenePath, const std::string& outPath);

private:
    bool load(const std::string& scenePath);
    bool cameraOf(const Scene& scene, const std::string& scenePath, Camera& camera,
                  std::string& error, bool announce) const;
    bool poseAndFrame(const std::string& scenePath, int frame, Camera& camera,
                      std::shared_ptr<FrameMotion>& motion);
    bool findTransparent(const GBufferRenderer& renderer, const std::string& scenePath,
                         std::vector<std::pair<DeepGBuffer, long long>>& kept, bool& found) const;
    bool writeDeep(const GBufferRenderer& renderer, const std::string& scenePath,
                   const std::string& outPath, const std::optional<gbuffer::Moment>& moment,
                   std::vector<std::pair<DeepGBuffer, long long>>& kept,
                   std::chrono::steady_clock::time_point s0) const;
    bool writeFlat(const GBufferRenderer& renderer, const std::string& scenePath,
                   const std::string& outPath, const OIIO::ImageSpec& spec, double& traceMs) const;
    bool writeLightsOut(int frame, const Scene& scene, const std::string& scenePath) const;

    const app::Tool& m_tool;
    const Options& m_o;
    const GBufferParams& m_params;
    const std::optional<Camera> m_lookat;
    const app::FramePattern m_lightsOutput;
    const GBufferDepth m_depth;
    const size_t m_stillFrames;
    PosedScene m_loaded;
    std::string m_loadedPath;
    bool m_loadFailed = false; // a failure is reported once
    bool m_toldMoves = false;  // the loaded scene's motionSummary, once
    std::optional<std::pair<glm::dvec3, glm::dvec3>> m_frameBounds; // --frame-all's, animated
};

bool GBufferFrames::load(const std::string& scenePath) {
    if (m_loadedPath == scenePath) return !m_loadFailed;
    m_toldMoves = false;
    m_loadedPath = scenePath;
    m_loadFailed = true; // until it is ready
    std::string error;
    if (!m_loaded.load(scenePath, SceneOptions{m_o.strict}, error))
        return m_tool.fail(error), false;
    Scene& scene = m_loaded.scene();
    for (const std::string& warning : scene.warnings)
        m_tool.warn(scenePath + ": " + warning);
    if (!m_loaded.selectAnimations(m_o.timing.animation, error)) {
        m_tool.fail(scenePath + ": " + error);
        return false;
    }
    if (!m_loaded.animated() && m_o.timing.given)
        m_tool.warn(scenePath + ": " + kNoAnimationPlayed +
                    "; --frame, --time and --fps change nothing");
    if (!m_loaded.animated() && m_stillFrames > 1)
        m_tool.warn(scenePath + ": " + kNoAnimationPlayed + "; --frames writes the same G-buffer " +
                    std::to_string(m_stillFrames) + " times");
    if (m_o.groundPlane) {
        const double y =
            m_o.groundY ? *m_o.groundY : (scene.meshes.empty() ? 0.0 : scene.boundsMin().y);
        addGroundPlane(scene, float(y));
        m_tool.info("ground plane (shadow catcher) at y = " + std::to_string(y));
    }
    // --frame-all frames the whole animation once: re-framed at each pose, the camera would
    // breathe, and its breathing would go into the motion layer.
    m_frameBounds.reset();
    if (m_o.frameAll && m_loaded.animated()) m_frameBounds = m_loaded.animationBounds();
    m_loadFailed = false;
    return true;
}

// The camera of a frame (chooseCamera: --lookat's, else the scene's, posed, with --fov and
// --frame-all). False with `error`; what the choice says is said when `announce`.
bool GBufferFrames::cameraOf(const Scene& scene, const std::string& scenePath, Camera& camera,
                             std::string& error, bool announce) const {
    CameraChoice choice;
    choice.name = m_o.cameraName;
    choice.lookat = m_lookat;
    choice.fovDegrees = m_o.camera.fovDegrees;
    choice.frameAll = m_o.frameAll;
    choice.bounds = m_frameBounds;
    std::vector<std::string> notes, warnings;
    const bool chosen =
        chooseCamera(scene, scenePath, choice, double(m_params.width) / double(m_params.height),
                     camera, error, notes, warnings);
    if (announce) m_tool.say(warnings, notes);
    return chosen;
}

// Poses the scene at frame `frame`'s time (the frames either side first, for the motion layer)
// and chooses its camera. A frame either side without a camera leaves its half of the motion
// layer 0, with a warning, as a point behind the camera does.
bool GBufferFrames::poseAndFrame(const std::string& scenePath, int frame, Camera& camera,
                                 std::shared_ptr<FrameMotion>& motion) {
    std::string error, sideError[2];
    int side = 0;
    auto around = [&](const Scene& s, Camera& c) {
        return cameraOf(s, scenePath, c, sideError[side++], false);
    };
    const app::FrameTiming& timing = m_o.timing;
    const double time = timing.timeOf(frame);
    if (!m_loaded.pose(timing.timeBefore(frame), time, timing.timeAfter(frame), around, motion,
                       error)) {
        m_tool.fail(scenePath + ": " + error);
        return false;
    }
    if (!cameraOf(m_loaded.scene(), scenePath, camera, error, true))
        return m_tool.fail(error), false;
    const char* sideName[2] = {"previous", "next"};
    for (int k = 0; k < 2; ++k)
        if (!sideError[k].empty())
            m_tool.warn(sideError[k] + " (at the " + sideName[k] +
                        " frame: that half of the motion layer is 0)");
    if (m_loaded.animated())
        m_tool.info("time " + std::to_string(time) + " s; motion layer written");
    if (const std::string moves = m_loaded.motionSummary(); !moves.empty() && !m_toldMoves) {
        m_tool.info(scenePath + ": " + moves);
        m_toldMoves = true;
    }
    return true;
}

bool GBufferFrames::frame(int frame, const std::string& scenePath, const std::string& outPath) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!load(scenePath)) return false;
    const double time = m_o.timing.timeOf(frame);
    Camera camera;
    std::shared_ptr<FrameMotion> motion;
    if (!poseAndFrame(scenePath, frame, camera, motion)) return false;
    const Scene& scene = m_loaded.scene();

    const auto t1 = std::chrono::steady_clock::now();
    GBufferParams frameParams = m_params;
    frameParams.motion = motion;
    const GBufferRenderer renderer(scene, camera, frameParams, m_loaded.caster());
    if (!renderer.ok()) {
        m_tool.fail(scenePath + ": " + renderer.error());
        return false;
    }
    // When the file plays, which moment of it this is, so that a compositor can tell and
    // dhdr-light --scene poses the scene where the pixels are.
    const std::optional<gbuffer::Moment> moment = m_loaded.moment(time, m_o.timing.moment.fps);
    OIIO::ImageSpec spec = renderer.spec();
    gbuffer::stampGBuffer(spec, scenePath, moment);
    if (tracesLayers(m_depth, scene) || (m_params.samples > 1 && m_depth != GBufferDepth::Flat)) {
        // Without --deep, a deep file is written only when some pixel holds a partly
        // transparent surface or several rays: the layers are traced strip by strip until one is
        // found (all of them when none is), then traced again (or taken from those kept) and
        // written a strip at a time, so memory stays at one strip whatever the image size.
        const auto s0 = std::chrono::steady_clock::now();
        std::vector<std::pair<DeepGBuffer, long long>> kept; // and its transparent samples
        bool deep = m_depth == GBufferDepth::Deep;
        if (!deep && !findTransparent(renderer, scenePath, kept, deep)) return false;
        if (deep) {
            return writeDeep(renderer, scenePath, outPath, moment, kept, s0) &&
                   writeLightsOut(frame, scene, scenePath);
        }
        m_tool.info(m_params.samples > 1 ? "no partly transparent surface in view and no pixel "
                                           "of several rays: writing a flat G-buffer"
                                         : "no partly transparent surface in view: writing a "
                                           "flat G-buffer");
    }
    double traceMs = 0.0;
    if (!writeFlat(renderer, scenePath, outPath, spec, traceMs)) return false;
    if (!writeLightsOut(frame, scene, scenePath)) return false;
    const auto t2 = std::chrono::steady_clock::now();
    auto ms = [](double v) { return std::to_string(int(v + 0.5)) + " ms"; };
    const double totalMs = std::chrono::duration<double, std::milli>(t2 - t1).count();
    m_tool.info("load " + ms(std::chrono::duration<double, std::milli>(t1 - t0).count()) +
                ", trace " + ms(traceMs) + ", write " + ms(totalMs - traceMs));
    return true;
}

// Traces the layers strip by strip until a partly transparent sample is found (`found`),
// keeping the strips traced while they fit kKeptBytes (none unless found). False after the
// tool's error.
bool GBufferFrames::findTransparent(const GBufferRenderer& renderer, const std::string& scenePath,
                                    std::vector<std::pair<DeepGBuffer, long long>>& kept,
                                    bool& found) const {
    app::Progress progress(m_tool, "dhdr-gbuffer: looking for transparent surfaces");
    DeepGBuffer strip;
    size_t keptBytes = 0;
    for (int y = 0; y < m_params.height && !found; y += kStrip) {
        const OIIO::ROI rows(0, m_params.width, y, std::min(y + kStrip, m_params.height));
        long long t = 0;
        if (!renderer.renderDeep(strip, rows, m_tool.threads(), &t)) {
            m_tool.fail(scenePath + ": cannot render the layers");
            return false;
        }
        found = writtenDeep(m_depth, t);
        keptBytes +=
            strip.values.size() * sizeof(float) + strip.first.size() * sizeof(std::uint32_t);
        if (keptBytes <= kKeptBytes)
            kept.emplace_back(strip, t);
        else
            kept.clear();
        progress.update(float(rows.yend) / float(m_params.height));
    }
    if (!found || keptBytes > kKeptBytes) kept.clear();
    return true;
}

// Traces the layers (or takes the strips `kept`) and writes them a strip at a time as a deep
// EXR, stamped as the flat one would be. `s0`: when the layers' work began.
bool GBufferFrames::writeDeep(const GBufferRenderer& renderer, const std::string& scenePath,
                              const std::string& outPath,
                              const std::optional<gbuffer::Moment>& moment,
                              std::vector<std::pair<DeepGBuffer, long long>>& kept,
                              std::chrono::steady_clock::time_point s0) const {
    long long transparent = 0, samples = 0;
    std::vector<OIIO::TypeDesc> deepFormats = gbuffer::channelFormats(renderer.deepChannelNames());
    app::AtomicOutput file(m_tool, outPath);
    app::Progress progress(m_tool, "dhdr-gbuffer: rendering layers");
    StripPipelineParams streaming;
    streaming.rows = kStrip;
    streaming.progress = progress.over();
    // A strip is written while the next is traced (as flat ones are), each in its slot.
    streaming.writeBehind = m_tool.threads() != 1;
    DeepGBuffer strips[2];
    StripStages stages;
    stages.process = [&](OIIO::ROI rows, int slot, std::string& e) {
        DeepGBuffer& strip = strips[slot];
        const size_t k = size_t(rows.ybegin / kStrip);
        long long t = 0;
        if (k < kept.size()) {
            strip = std::move(kept[k].first);
            t = kept[k].second;
        } else if (!renderer.renderDeep(strip, rows, m_tool.threads(), &t)) {
            e = scenePath + ": cannot render the layers";
            return false;
        }
        transparent += t;
        samples += (long long)strip.totalSamples();
        if (rows.ybegin > 0) return true;
        OIIO::ImageSpec deepSpec = strip.spec;
        deepSpec.y = 0;
        deepSpec.height = m_params.height;
        deepSpec.channelformats = deepFormats;
        gbuffer::stampGBuffer(deepSpec, scenePath, moment);
        if (file.file().openDeep(deepSpec)) return true;
        e = file.file().geterror();
        return false;
    };
    stages.write = [&](OIIO::ROI rows, int slot, std::string& e) {
        OIIO::DeepData data;
        toDeepData(strips[slot], rows.ybegin, rows.yend, data, deepFormats);
        if (file.file().writeDeepRows(rows.ybegin, rows.yend, data)) return true;
        e = file.file().geterror();
        return false;
    };
    const OIIO::ROI frameRows(0, m_params.width, 0, m_params.height);
    if (std::string e; !runStrips(frameRows, streaming, stages, e)) {
        m_tool.fail(e);
        return false;
    }
    if (!file.commit()) return false;
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - s0).count();
    m_tool.info("deep: " + std::to_string(samples) + " samples, " + std::to_string(transparent) +
                (m_params.samples > 1 ? " partly transparent or of pixels of several rays; "
                                      : " partly transparent; ") +
                std::to_string(int(ms + 0.5)) + " ms");
    if (samples == 0) m_tool.warn(outPath + ": no surface in view: every pixel is background");
    return true;
}

// Traces and writes the flat G-buffer strip by strip: each strip is traced in parallel and
// written while the next is traced, and memory stays at two strips whatever the image size.
// `traceMs` receives the tracing's time.
bool GBufferFrames::writeFlat(const GBufferRenderer& renderer, const std::string& scenePath,
                              const std::string& outPath, const OIIO::ImageSpec& spec,
                              double& traceMs) const {
    app::AtomicOutput file(m_tool, outPath);
    file.file().setThroughOpenExr(true);
    OIIO::ImageSpec compressed = spec; // --compression, when given, replaces it
    compressed.attribute("compression", kDefaultCompression);
    if (!file.open(compressed, gbuffer::channelFormats(spec.channelnames))) return false;
    long long covered = 0;
    StripPipelineParams streaming;
    streaming.rows = kStrip;
    streaming.writeBehind = m_tool.threads() != 1;
    app::Progress progress(m_tool, "dhdr-gbuffer: rendering");
    streaming.progress = progress.over();
    StripPipeline pipeline(OIIO::ROI(0, m_params.width, 0, m_params.height), streaming);
    pipeline.setOutput(file.file());
    const bool rendered = pipeline.run([&](StripContext& strip) {
        if (!renderer.render(*strip.output, strip.rows, m_tool.threads())) {
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
        m_tool.fail(pipeline.error());
        return false;
    }
    traceMs = pipeline.processMs();
    if (!file.commit()) return false;
    if (covered == 0)
        m_tool.warn(outPath + ": no surface in view: every pixel is background (check the "
                              "camera, or the scene's geometry)");
    return true;
}

bool GBufferFrames::writeLightsOut(int frame, const Scene& scene,
                                   const std::string& scenePath) const {
    if (m_o.lightsOut.empty()) return true;
    const std::string lightsPath = m_lightsOutput.path(frame);
    if (scene.lights.empty())
        m_tool.warn(scenePath + ": the scene has no lights; writing an empty list");
    if (!m_tool.writeText(formatLights(scene.lights), lightsPath)) return false;
    const size_t n = scene.lights.size();
    m_tool.info(std::to_string(n) + (n == 1 ? " light" : " lights") + " written to " + lightsPath);
    return true;
}

int run(int argc, char** argv) {
    app::CommandLine cl(
        "dhdr-gbuffer", "SCENE -o GBUFFER.exr [options]",
        "Casts one primary ray per pixel (Embree) through a glTF 2.0 or OBJ scene "
        "(Assimp) and\nwrites the G-buffer channels of docs/gbuffer.md: A Z P.* N.* "
        "albedo.* roughness\nmetallic emission.* id.object id.material.");
    Options o;
    declareOptions(cl, o);
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-gbuffer", cl);
    if (cl.inputs().size() != 1) return usage("give one scene file");
    const std::string& path = cl.inputs()[0];
    if (o.info) {
        Scene scene;
        std::string error;
        if (!loadScene(path, scene, error, SceneOptions{o.strict})) return tool.fail(error);
        std::fputs(describeScene(scene, path).c_str(), stdout);
        return app::kExitSuccess;
    }
    if (const int status = o.timing.check(tool); status >= 0) return status;
    app::FramePlan plan;
    if (const int status = app::planFrames(tool, cl.inputs(), plan); status >= 0) return status;
    if (const int status = o.timing.checkTimes(tool, plan.frames); status >= 0) return status;
    // One frame has one lights file: a pattern would write frame 0's name whatever --frame is.
    if (!plan.output.isSequence() && app::FramePattern(o.lightsOut).isSequence())
        return usage("--lights-out " + o.lightsOut +
                     ": a frame pattern in --lights-out needs one in the output too "
                     "(-o out.####.exr with --frames A-B)");
    GBufferParams params;
    if (const int status = parseImage(o, params); status >= 0) return status;
    std::optional<Camera> lookat;
    if (const int status = parseLookat(o.lookat, lookat); status >= 0) return status;
    const size_t stillFrames = plan.inputs[0].isSequence() ? 1 : plan.frames.size();
    GBufferFrames frames(tool, o, params, std::move(lookat), stillFrames);
    return app::runFrames(tool, plan, [&](int frame, const auto& in, const std::string& outPath) {
        return frames.frame(frame, in[0], outPath);
    });
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-gbuffer", [&] { return run(argc, argv); });
}
