#include "py_scene.h"

#include "py_deep.h"
#include "py_interrupt.h"
#include "py_ops.h"

#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_depth.h>
#include <dhdr/deferred/gbuffer/gbuffer_stamp.h>
#include <dhdr/deferred/gbuffer/gbuffer_time.h>
#include <dhdr/deferred/geometry/posed_scene.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/animation.h>
#include <dhdr/deferred/scene/camera.h>
#include <dhdr/deferred/scene/scene_camera.h>
#include <dhdr/deferred/scene/scene_info.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <dhdr/io/image_output.h>
#include <dhdr/io/pixel_limit.h>
#include <glm/gtc/constants.hpp>
#include <optional>
#include <pybind11/stl.h>

namespace dhdr::python {

namespace {

using namespace pybind11::literals;

SceneHandle loadSceneFile(const std::string& path, bool strict, const py::object& groundPlane) {
    SceneHandle h{path, std::make_shared<Scene>()};
    std::string error;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        ok = loadScene(path, *h.scene, error, SceneOptions{strict});
    }
    if (!ok) raiseError(error);
    // dhdr-gbuffer --ground-plane [Y]: True puts it at the scene's lowest point.
    if (py::isinstance<py::bool_>(groundPlane)) {
        if (groundPlane.cast<bool>())
            addGroundPlane(*h.scene, float(h.scene->meshes.empty() ? 0.0 : h.scene->boundsMin().y));
    } else if (!groundPlane.is_none()) {
        addGroundPlane(*h.scene, groundPlane.cast<float>());
    }
    for (const std::string& w : h.scene->warnings)
        warn(path + ": " + w);
    return h;
}

py::list cameras(const SceneHandle& h) {
    py::list out;
    for (const SceneCamera& c : h.scene->cameras) {
        py::dict d("name"_a = c.name, "orthographic"_a = c.camera.orthographic,
                   "aspect"_a = c.aspect, "problem"_a = c.problem);
        if (c.camera.orthographic)
            d["ymag"] = c.camera.ymag;
        else
            d["yfov_degrees"] = glm::degrees(c.camera.yfov);
        out.append(d);
    }
    return out;
}

// Scene.materials: the materials in use (materialsInUse), as --info lists them.
py::list materials(const SceneHandle& h) {
    const Scene& scene = *h.scene;
    py::list out;
    for (const int i : materialsInUse(scene)) {
        const Material& m = scene.materials[size_t(i)];
        py::dict textures;
        for (const MaterialTexture& t : materialTextures(m)) {
            const TextureTransform& x = t.ref->transform;
            textures[t.key] = py::dict("name"_a = scene.textures[size_t(t.ref->texture)].name,
                                       "offset"_a = py::make_tuple(x.offset.x, x.offset.y),
                                       "rotation"_a = x.rotation,
                                       "scale"_a = py::make_tuple(x.scale.x, x.scale.y));
        }
        py::list extensions, notRead;
        if (const auto e = scene.materialExtensions.find(i); e != scene.materialExtensions.end())
            for (const MaterialExtension& x : e->second) {
                extensions.append(x.name);
                if (!x.rendered) notRead.append(x.name);
            }
        py::dict d("name"_a = m.name,
                   "base_color"_a = py::make_tuple(m.baseColor.r, m.baseColor.g, m.baseColor.b),
                   "alpha"_a = m.alpha, "alpha_mode"_a = alphaModeName(m.alphaMode),
                   "alpha_cutoff"_a = m.alphaCutoff, "metallic"_a = m.metallic,
                   "roughness"_a = m.roughness,
                   "emission"_a = py::make_tuple(m.emission.r, m.emission.g, m.emission.b),
                   "normal_scale"_a = m.normalScale, "clearcoat"_a = m.clearcoat,
                   "clearcoat_roughness"_a = m.clearcoatRoughness,
                   "sheen_color"_a = py::make_tuple(m.sheenColor.r, m.sheenColor.g, m.sheenColor.b),
                   "sheen_roughness"_a = m.sheenRoughness, "transmission"_a = m.transmission,
                   "attenuation_color"_a = py::make_tuple(
                       m.attenuationColor.r, m.attenuationColor.g, m.attenuationColor.b),
                   "attenuation_distance"_a = m.attenuationDistance, "textures"_a = textures,
                   "extensions"_a = extensions, "extensions_not_read"_a = notRead);
        out.append(d);
    }
    return out;
}

py::list animations(const SceneHandle& h) {
    py::list out;
    if (!h.scene->rig) return out;
    for (const Animation& a : h.scene->rig->animations)
        out.append(py::dict("name"_a = a.name, "duration"_a = a.duration(), "start"_a = a.start,
                            "end"_a = a.end, "channels"_a = a.channels.size(),
                            "problem"_a = a.problem));
    return out;
}

// --animation's value: a name, an index or 'all'; None is the file's first.
std::string animationSelection(const py::object& animation) {
    if (animation.is_none()) return "";
    if (py::isinstance<py::int_>(animation) && !py::isinstance<py::bool_>(animation))
        return std::to_string(animation.cast<long long>());
    if (py::isinstance<py::str>(animation)) return animation.cast<std::string>();
    throw py::type_error("animation: expected a name, an index or 'all'");
}

// frame=: None, or a whole number (a Python int of any size, numpy's too), its range
// kMomentIntTable's; a float, or a number past a long long, is told by its keyword.
std::optional<long long> frameOf(const py::object& frame) {
    if (frame.is_none()) return std::nullopt;
    if (py::isinstance<py::bool_>(frame) || !py::hasattr(frame, "__index__"))
        throw py::type_error("frame: expected a whole number, got " +
                             py::repr(frame).cast<std::string>());
    const py::int_ whole(frame.attr("__index__")());
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(whole.ptr(), &overflow);
    if (overflow != 0)
        throw py::value_error(std::string(paramName(kMomentIntTable[0], Spelling::Keyword)) + ": " +
                              py::str(py::handle(whole)).cast<std::string>() + " is outside " +
                              intRangeText(kMomentIntTable[0]));
    return v;
}

// The moment an animated render shows, from render_gbuffer's keywords as dhdr-gbuffer reads
// --animation, --frame, --time and --fps; `playing` empty: the scene does not move.
struct Moment {
    std::vector<int> playing;
    double time = 0.0;
};

Moment momentOf(const SceneHandle& h, const py::object& animation, std::optional<long long> frame,
                std::optional<double> time, double fps) {
    if (frame && time) throw py::value_error("frame and time exclude each other");
    // dhdr-gbuffer's --fps, --time and --frame ranges; the frame as Python's integer.
    MomentChoice given;
    given.fps = fps;
    if (time) given.time = *time;
    checkParams(given, kMomentFloatTable);
    if (frame)
        if (const std::string e = rangeProblem(kMomentIntTable[0], *frame, Spelling::Keyword);
            !e.empty())
            throw py::value_error(e);
    Moment m;
    const std::vector<Animation> none;
    const std::vector<Animation>& all = h.scene->rig ? h.scene->rig->animations : none;
    if (std::string error;
        !selectAnimations(all, animationSelection(animation), m.playing, error)) {
        // A name or index the file lacks is the caller's mistake; an animation the file cannot
        // play is the file's.
        if (error.rfind("animation '", 0) == 0) raiseError(h.path + ": " + error);
        throw py::value_error(h.path + ": " + error);
    }
    if (m.playing.empty() && (frame || time))
        warn(h.path + ": " + kNoAnimationPlayed + "; --frame, --time and --fps change nothing");
    // Frame N shows time N / fps, frame 0 time 0 (docs/animation.md), the default.
    m.time = time ? *time : double(frame ? *frame : 0) / fps;
    return m;
}

// Scene.posed: a copy of the scene at one moment, its meshes, cameras and lights where the
// animation puts them (what dhdr-gbuffer --frame renders and --lights-out writes), without its
// animations, so that it stands still there for render_gbuffer and light(scene=).
SceneHandle posed(const SceneHandle& h, const py::object& time, const py::object& frame, double fps,
                  const py::object& animation) {
    const Moment moment =
        momentOf(h, animation, frameOf(frame),
                 time.is_none() ? std::nullopt : std::optional<double>(time.cast<double>()), fps);
    SceneHandle out{h.path, nullptr};
    {
        py::gil_scoped_release gil;
        out.scene = std::make_shared<Scene>(stillCopy(*h.scene, moment.playing, moment.time));
    }
    return out;
}

// render_gbuffer's pixel_samples, pixel_sampling, pixel_filter and filter_width.
struct PixelSampling {
    int samples;
    std::string pixels, filter;
    float filterWidth;
};

// render_gbuffer's size, max_layers, texture_filter and pixel sampling, checked as dhdr-gbuffer
// checks
// --size, --max-layers and --texture-filter.
GBufferParams gbufferParams(std::pair<int, int> size, int maxLayers,
                            const std::string& textureFilter, const PixelSampling& sampling) {
    GBufferParams params;
    params.maxLayers = maxLayers;
    params.samples = sampling.samples;
    params.filterWidth = sampling.filterWidth;
    checkParams(params, kGBufferParamTable);
    checkParams(params, kGBufferFloatTable);
    if (const std::string e = samplesError(params.samples); !e.empty())
        throw py::value_error("pixel_samples" + e.substr(e.find(' ')));
    std::string error;
    const std::string* choices[] = {&textureFilter, &sampling.pixels, &sampling.filter};
    for (size_t i = 0; i < 3; ++i)
        if (!setChoice(kGBufferChoiceTable[i], params, *choices[i], Spelling::Keyword, error))
            throw py::value_error(error);
    params.width = size.first;
    params.height = size.second;
    if (params.width <= 0 || params.height <= 0)
        throw py::value_error("size: expected (width, height) of positive numbers");
    if (const std::string e = pixelLimitError(params.width, params.height); !e.empty())
        throw py::value_error("size: " + e);
    return params;
}

// deep: True (--deep), False (--flat) or 'auto', the tool's default: deep when a partly
// transparent surface is in view.
GBufferDepth depthOf(const py::object& deep) {
    if (py::isinstance<py::str>(deep)) {
        if (deep.cast<std::string>() != "auto")
            throw py::value_error("deep must be True, False or 'auto'");
        return GBufferDepth::Auto;
    }
    return deep.cast<bool>() ? GBufferDepth::Deep : GBufferDepth::Flat;
}

// render_gbuffer's camera, lookat, fov (checked; 0: the camera's) and frame_all, as
// dhdr-gbuffer's --camera, --lookat, --fov and --frame-all.
CameraChoice cameraChoice(const std::string& camera, const py::object& lookat, double fov,
                          bool frameAll) {
    CameraChoice choice;
    choice.name = camera;
    choice.fovDegrees = fov;
    checkParams(choice, kCameraFloatTable);
    choice.frameAll = frameAll;
    if (lookat.is_none()) return choice;
    // (eye, target[, up]) as dhdr-gbuffer --lookat, 39.6 degrees unless fov says.
    const std::vector<double> v = lookat.cast<std::vector<double>>();
    if (v.size() != 6 && v.size() != 9)
        throw py::value_error("lookat needs 6 or 9 numbers (eye, target[, up])");
    const glm::dvec3 eye(v[0], v[1], v[2]), target(v[3], v[4], v[5]);
    const glm::dvec3 up = v.size() == 9 ? glm::dvec3(v[6], v[7], v[8]) : glm::dvec3(0, 1, 0);
    if (glm::length(target - eye) < 1e-9 * std::max(1.0, glm::length(eye)))
        throw py::value_error("lookat: the eye and the target are the same point");
    if (glm::length(up) == 0.0) throw py::value_error("lookat: the up vector is zero");
    choice.lookat = Camera::lookAt(eye, target, up, glm::radians(39.6));
    return choice;
}

// What render_gbuffer renders, without the GIL: the G-buffer flat or deep, or why not.
struct Rendered {
    OIIO::ImageBuf gbuf;
    DeepHandle layers;
    bool deep = false, ok = false;
    std::string error, cameraError;
    std::vector<std::string> warnings; // what the frame's camera choice warns about
};

// Traces the G-buffer of `scene` (with `caster`, or its own) from the camera `choice` gives,
// flat or deep as `depth` says.
void trace(const SceneHandle& h, const Scene& scene, std::shared_ptr<const RayCaster> caster,
           const GBufferParams& params, const CameraChoice& choice, GBufferDepth depth,
           int nthreads, Rendered& out) {
    std::vector<std::string> notes;
    Camera cam;
    const double aspect = double(params.width) / double(params.height);
    if (!chooseCamera(scene, h.path, choice, aspect, cam, out.cameraError, notes, out.warnings,
                      Spelling::Keyword))
        return;
    const GBufferRenderer renderer =
        caster ? GBufferRenderer(scene, cam, params, caster) : GBufferRenderer(scene, cam, params);
    if (!renderer.ok()) {
        out.error = h.path + ": " + renderer.error();
        return;
    }
    if (tracesLayers(depth, scene) || (params.samples > 1 && depth != GBufferDepth::Flat)) {
        long long transparent = 0;
        out.ok = renderer.renderDeep(*out.layers.g, {}, nthreads, &transparent);
        if (!out.ok) out.error = h.path + ": cannot render the layers";
        out.deep = writtenDeep(depth, transparent);
    }
    if (!out.deep && out.error.empty()) {
        out.ok = renderer.render(out.gbuf, {}, nthreads);
        if (!out.ok) out.error = h.path + ": " + out.gbuf.geterror();
    }
}

py::object render(const SceneHandle& h, const std::string& camera, const py::object& lookat,
                  double fov, std::pair<int, int> size, bool frameAll, const py::object& deepGiven,
                  int maxLayers, const std::string& textureFilter, int pixelSamples,
                  const std::string& pixelSampling, const std::string& pixelFilter,
                  float filterWidth, const py::object& time, const py::object& frame, double fps,
                  const py::object& animation, int nthreads) {
    const GBufferDepth depth = depthOf(deepGiven);
    GBufferParams params = gbufferParams(size, maxLayers, textureFilter,
                                         {pixelSamples, pixelSampling, pixelFilter, filterWidth});
    if (depth == GBufferDepth::Flat && params.samples > 1)
        throw py::value_error("pixel_samples " + std::to_string(params.samples) +
                              ": several rays a pixel need a deep G-buffer (deep=True or 'auto')");
    const Moment moment =
        momentOf(h, animation, frameOf(frame),
                 time.is_none() ? std::nullopt : std::optional<double>(time.cast<double>()), fps);
    const CameraChoice choice = cameraChoice(camera, lookat, fov, frameAll);
    const double aspect = double(params.width) / double(params.height);
    Rendered out;
    // Ctrl-C stops the rows not begun and raises KeyboardInterrupt (py_interrupt.h).
    std::atomic<bool> cancel{false};
    params.cancel = &cancel;
    runInterruptibly(cancel, [&] {
        // An animated render poses its own copy of the scene, as dhdr-gbuffer --frame does:
        // the frames before and after first (the motion layer), then this one, and builds its
        // ray caster on it, so that renders of one dhdr.Scene at other times may run at once.
        PosedScene posed;
        if (!moment.playing.empty()) {
            posed.hold(h.scene, h.path);
            posed.play(moment.playing);
            // The cameras either side say nothing: what the camera warns about is said for the
            // frame itself only, as the tool does.
            auto around = [&](const Scene& s, Camera& c) {
                std::vector<std::string> notes, warnings;
                return chooseCamera(s, h.path, choice, aspect, c, out.cameraError, notes, warnings,
                                    Spelling::Keyword);
            };
            std::shared_ptr<FrameMotion> motion;
            if (std::string e; !posed.pose(moment.time, 1.0 / fps, around, motion, e)) {
                if (!e.empty()) out.error = h.path + ": " + e;
            }
            params.motion = motion;
        }
        if (out.cameraError.empty() && out.error.empty())
            trace(h, posed.animated() ? posed.scene() : *h.scene, posed.caster(), params, choice,
                  depth, nthreads, out);
        // What dhdr-gbuffer records: the scene file and its fingerprint (dhdr-light compares
        // it with --scene), and for an animated frame which moment it shows.
        if (out.ok)
            gbuffer::stampGBuffer(out.deep ? out.layers.g->spec : out.gbuf.specmod(), h.path,
                                  posed.moment(moment.time, fps));
    });
    for (const std::string& w : out.warnings)
        warn(w);
    if (!out.cameraError.empty()) throw py::value_error(out.cameraError);
    if (!out.ok) raiseError(out.error);
    if (out.deep) return py::cast(std::move(out.layers));
    return py::cast(Image::fromBuf(std::move(out.gbuf)));
}

} // namespace

const RayCaster& SceneHandle::caster() const {
    {
        py::gil_scoped_release gil;
        std::call_once(rays->once, [&] { rays->caster = std::make_unique<RayCaster>(*scene); });
    }
    if (!rays->caster->ok()) raiseError(path + ": " + rays->caster->error());
    return *rays->caster;
}

void bindScene(py::module_& m) {
    py::class_<SceneHandle>(
        m, "Scene", R"(A glTF 2.0 (.gltf, .glb) or OBJ scene, loaded as dhdr-gbuffer loads it
(Assimp, with the glTF JSON for what Assimp loses; docs/scenes.md). strict: a texture that
cannot be read is an error (else a RuntimeWarning and magenta). ground_plane: True (at the
lowest point) or a height adds dhdr-gbuffer --ground-plane's shadow catcher.)")
        .def(py::init(&loadSceneFile), "path"_a, py::kw_only(), "strict"_a = false,
             "ground_plane"_a = py::none())
        .def_readonly("path", &SceneHandle::path)
        .def_property_readonly("cameras", &cameras,
                               "The scene's cameras: name, projection, field of view or ymag, "
                               "aspect, and why one cannot be rendered from.")
        .def_property_readonly(
            "lights",
            [](const SceneHandle& h) {
                const py::object doc =
                    py::module_::import("json").attr("loads")(formatLights(h.scene->lights));
                return py::object(doc["lights"]);
            },
            "The scene's punctual lights as lights-file dicts (dhdr-gbuffer --lights-out).")
        .def_property_readonly("objects", [](const SceneHandle& h) { return h.scene->objectNames; })
        .def_property_readonly(
            "materials", &materials,
            "The materials the scene's meshes use (not Assimp's unused default), as dhdr-gbuffer "
            "--info lists them: name, base_color, alpha, alpha_mode ('opaque', 'mask', "
            "'blend'), alpha_cutoff, metallic, roughness, emission (linear radiance), "
            "normal_scale, clearcoat and clearcoat_roughness (KHR_materials_clearcoat; 0 without "
            "a coat), sheen_color and sheen_roughness (KHR_materials_sheen; 0 without a sheen), "
            "transmission (KHR_materials_transmission; 0: opaque), attenuation_color and "
            "attenuation_distance (KHR_materials_volume; inf: no absorption), "
            "textures (by slot: base_color, emissive, normal; each its name and "
            "KHR_texture_transform offset, rotation, scale), extensions (the glTF extensions the "
            "material names) and extensions_not_read (those dhdr does not render).")
        .def_property_readonly("bounds",
                               [](const SceneHandle& h) {
                                   const glm::dvec3 lo = h.scene->boundsMin(),
                                                    hi = h.scene->boundsMax();
                                   return py::make_tuple(py::make_tuple(lo.x, lo.y, lo.z),
                                                         py::make_tuple(hi.x, hi.y, hi.z));
                               })
        .def_property_readonly("warnings", [](const SceneHandle& h) { return h.scene->warnings; })
        .def_property_readonly(
            "animations", &animations,
            "The file's animations, as dhdr-gbuffer --info lists them (index = position): name, "
            "duration, start and end (its first and last key, seconds), channels, and the "
            "problem that keeps it from playing (empty when it plays).")
        .def("posed", &posed, py::kw_only(), "time"_a = py::none(), "frame"_a = py::none(),
             "fps"_a = MomentChoice{}.fps, "animation"_a = py::none(),
             R"(The scene at one moment of its animation (time seconds, or frame / fps; animation as
render_gbuffer takes them), standing still there: its meshes, cameras and lights where
dhdr-gbuffer --frame renders them (lights: what --lights-out writes for that frame), without
animations. light(scene=...) then traces shadows from the posed geometry.)")
        .def(
            "info", [](const SceneHandle& h) { return describeScene(*h.scene, h.path); },
            "What the scene holds, as dhdr-gbuffer --info prints it.")
        .def("__repr__", [](const SceneHandle& h) {
            return "dhdr.Scene('" + h.path + "', " + std::to_string(h.scene->meshes.size()) +
                   " meshes)";
        });

    m.def("render_gbuffer", &render, "scene"_a, py::kw_only(), "camera"_a = "",
          "lookat"_a = py::none(), "fov"_a = CameraChoice{}.fovDegrees,
          "size"_a = std::pair<int, int>{1920, 1080}, "frame_all"_a = false, "deep"_a = false,
          "max_layers"_a = GBufferParams{}.maxLayers,
          "texture_filter"_a =
              choiceName(kGBufferChoiceTable[0].names, kGBufferChoiceTable[0].get(GBufferParams{})),
          "pixel_samples"_a = GBufferParams{}.samples,
          "pixel_sampling"_a =
              choiceName(kGBufferChoiceTable[1].names, kGBufferChoiceTable[1].get(GBufferParams{})),
          "pixel_filter"_a =
              choiceName(kGBufferChoiceTable[2].names, kGBufferChoiceTable[2].get(GBufferParams{})),
          "filter_width"_a = GBufferParams{}.filterWidth, "time"_a = py::none(),
          "frame"_a = py::none(), "fps"_a = MomentChoice{}.fps, "animation"_a = py::none(),
          "nthreads"_a = 0,
          R"(A flat G-buffer of the scene (dhdr-gbuffer): one primary ray per pixel, the channels of
docs/gbuffer.md as float32 by name, the header (camera matrices, name tables, Cryptomatte
manifests) in attributes. camera: a scene camera by name (default the first); lookat:
(eye, target[, up]) instead; fov: vertical degrees; size: (width, height); frame_all: move
the camera back until the scene fits. write_gbuffer() writes it in the contract's types.
deep=True (--deep): a DeepGBuffer, per pixel every surface up to the first opaque one, at
most max_layers (--max-layers) samples a pixel; deep='auto' (the tool's default): a
DeepGBuffer when a partly transparent surface is in view, else the flat Image.
texture_filter (--texture-filter): 'anisotropic' (default), 'trilinear' or 'bilinear'.
pixel_samples (--pixel-samples, a square): rays a pixel takes where it needs several, drawn
from pixel_filter ('blackman-harris', 'gaussian' or 'box') filter_width pixels wide, in the
pixels pixel_sampling says ('adaptive': edges, creases, steps, thin things; 'all'); over 1
needs deep=True or 'auto' and gives a DeepGBuffer (docs/gbuffer.md).
A scene with animations is posed as dhdr-gbuffer --frame/--time poses it: at time seconds,
or frame / fps (frame 0, time 0, by default); animation: the one that plays, by name or
index, or 'all' (default the file's first, --animation). Its G-buffer has the motion layer
(motion.X, .Y, .Z, .W: Blender's Vector pass, pixels) and dhdr:animationTime, dhdr:fps and
dhdr:animation in its header. Each animated call poses its own copy of the scene
(docs/animation.md).)");

    m.def(
        "write_gbuffer",
        [](const std::string& path, const Image& gbuffer) {
            checkImageName(path, "path");
            const ImageView v = view(gbuffer);
            // The contract's channels (with or without occlusion), then the motion layer of an
            // animated frame.
            if (!gbuffer::isWrittenLayout(v.buf.spec().channelnames, false))
                throw py::value_error("gbuffer: not the channels of a dhdr G-buffer, in order "
                                      "(render_gbuffer's)");
            std::string error;
            {
                py::gil_scoped_release gil;
                ImageOutputOptions options;
                options.software = "dhdr python module (dhdr " DHDR_VERSION ")";
                ImageFileOutput file(path, options);
                if (!file.open(v.buf.spec(), gbuffer::channelFormats(v.buf.spec().channelnames)) ||
                    !file.writeRows(v.buf, v.buf.roi()) || !file.commit())
                    error = file.geterror();
            }
            if (!error.empty()) raiseError(error);
        },
        "path"_a, "gbuffer"_a,
        "Writes a G-buffer as dhdr-gbuffer does: each channel in the contract's type (half, "
        "float or uint), atomically.");
}

} // namespace dhdr::python
