#include "py_scene.h"

#include "py_deep.h"
#include "py_ops.h"

#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_time.h>
#include <dhdr/deferred/render/gbuffer_render.h>
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

// The moment an animated render shows, from render_gbuffer's keywords as dhdr-gbuffer reads
// --animation, --frame, --time and --fps; `playing` empty: the scene does not move.
struct Moment {
    std::vector<int> playing;
    double time = 0.0;
};

Moment momentOf(const SceneHandle& h, const py::object& animation, std::optional<long long> frame,
                std::optional<double> time, double fps) {
    if (frame && time) throw py::value_error("frame and time exclude each other");
    checkRange("fps", fps, 0.0, 1e6, true, false);
    // dhdr-gbuffer's --frame and --time ranges (apps/common/frames.h).
    if (frame && (*frame < -99999999 || *frame > 999999999))
        throw py::value_error("frame: " + std::to_string(*frame) +
                              " is not a frame number in [-99999999, 999999999]");
    if (time) checkRange("time", *time, -1e9, 1e9);
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
        warn(h.path + ": the scene has no animation; --frame, --time and --fps change nothing");
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
        momentOf(h, animation,
                 frame.is_none() ? std::nullopt : std::optional<long long>(frame.cast<long long>()),
                 time.is_none() ? std::nullopt : std::optional<double>(time.cast<double>()), fps);
    SceneHandle out{h.path, std::make_shared<Scene>(*h.scene)};
    {
        py::gil_scoped_release gil;
        if (!moment.playing.empty()) ScenePoser(*out.scene, moment.playing).pose(moment.time);
        // Standing still: traced as its triangles lie, no mesh an instance.
        out.scene->rig.reset();
        for (Mesh& mesh : out.scene->meshes)
            mesh.instance.reset();
    }
    return out;
}

py::object render(const SceneHandle& h, const std::string& camera, const py::object& lookat,
                  double fov, std::pair<int, int> size, bool frameAll, const py::object& deepGiven,
                  int maxLayers, const py::object& time, const py::object& frame, double fps,
                  const py::object& animation, int nthreads) {
    // deep: True (--deep), False (--flat) or 'auto', the tool's default: deep when a partly
    // transparent surface is in view.
    const bool autoDeep = py::isinstance<py::str>(deepGiven);
    if (autoDeep && deepGiven.cast<std::string>() != "auto")
        throw py::value_error("deep must be True, False or 'auto'");
    bool deep = !autoDeep && deepGiven.cast<bool>();
    GBufferParams params;
    if (maxLayers < 1 || maxLayers > 64)
        throw py::value_error("max_layers: " + std::to_string(maxLayers) + " is outside [1, 64]");
    params.maxLayers = maxLayers;
    params.width = size.first;
    params.height = size.second;
    if (params.width <= 0 || params.height <= 0)
        throw py::value_error("size: expected (width, height) of positive numbers");
    if (const std::string e = pixelLimitError(params.width, params.height); !e.empty())
        throw py::value_error("size: " + e);
    if (!(fov >= 0.0 && fov < 180.0)) throw py::value_error("fov: must be in (0, 180) degrees");
    const Moment moment =
        momentOf(h, animation,
                 frame.is_none() ? std::nullopt : std::optional<long long>(frame.cast<long long>()),
                 time.is_none() ? std::nullopt : std::optional<double>(time.cast<double>()), fps);
    CameraChoice choice;
    choice.name = camera;
    choice.fovDegrees = fov;
    choice.frameAll = frameAll;
    if (!lookat.is_none()) {
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
    }
    const double aspect = double(params.width) / double(params.height);
    std::string cameraError, error;
    std::vector<std::string> warnings;
    // The camera of the scene as posed (chooseCamera: lookat's, else the scene's, with fov and
    // frame_all); what it warns about is said for the frame itself only, as the tool does.
    auto cameraOf = [&](const Scene& s, Camera& c, bool announce) {
        std::vector<std::string> notes, said;
        const bool ok = chooseCamera(s, h.path, choice, aspect, c, cameraError, notes, said);
        if (announce) warnings = said;
        return ok;
    };
    OIIO::ImageBuf gbuf;
    DeepHandle layers;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        // An animated render poses its own copy of the scene, as dhdr-gbuffer --frame does:
        // the frames before and after first (the motion layer), then this one, and builds its
        // ray caster on it, so that renders of one dhdr.Scene at other times may run at once.
        std::shared_ptr<const Scene> scene = h.scene;
        std::shared_ptr<RayCaster> caster;
        if (!moment.playing.empty()) {
            auto posed = std::make_shared<Scene>(*h.scene);
            ScenePoser poser(*posed, moment.playing);
            auto motion = std::make_shared<FrameMotion>();
            const double dt = 1.0 / fps;
            poser.pose(moment.time - dt);
            bool framed = cameraOf(*posed, motion->previousCamera, false);
            for (const Mesh& mesh : posed->meshes)
                motion->previous.push_back(mesh.positions);
            poser.pose(moment.time + dt);
            framed = framed && cameraOf(*posed, motion->nextCamera, false);
            for (const Mesh& mesh : posed->meshes)
                motion->next.push_back(mesh.positions);
            poser.pose(moment.time);
            if (framed) {
                caster =
                    std::make_shared<RayCaster>(*posed, posed->rig->movingMeshes(moment.playing));
                if (!caster->ok()) error = h.path + ": " + caster->error();
            }
            params.motion = motion;
            scene = posed;
        }
        Camera cam;
        if (cameraError.empty() && error.empty() && cameraOf(*scene, cam, true)) {
            const GBufferRenderer renderer = caster ? GBufferRenderer(*scene, cam, params, caster)
                                                    : GBufferRenderer(*scene, cam, params);
            // Only a Blend material makes a partly transparent surface.
            const bool blends =
                std::any_of(scene->materials.begin(), scene->materials.end(),
                            [](const Material& mat) { return mat.alphaMode == AlphaMode::Blend; });
            long long transparent = 0;
            if (!renderer.ok()) {
                error = h.path + ": " + renderer.error();
            } else if (deep || (autoDeep && blends)) {
                ok = renderer.renderDeep(*layers.g, {}, nthreads, &transparent);
                if (!ok) error = h.path + ": cannot render the layers";
                deep = deep || transparent > 0;
            }
            if (renderer.ok() && !deep && error.empty()) {
                ok = renderer.render(gbuf, {}, nthreads);
                if (!ok) error = h.path + ": " + gbuf.geterror();
            }
        }
        if (ok) {
            // What dhdr-gbuffer records: the scene file and its fingerprint (dhdr-light
            // compares it with --scene), and for an animated frame which moment it shows.
            OIIO::ImageSpec& spec = deep ? layers.g->spec : gbuf.specmod();
            spec.attribute("dhdr:source", h.path);
            if (!moment.playing.empty()) {
                gbuffer::Moment m;
                m.time = moment.time;
                m.fps = fps;
                m.animations = moment.playing;
                gbuffer::writeMoment(spec, m);
            }
            if (const std::string sha = sceneFingerprint(h.path); !sha.empty())
                spec.attribute(gbuffer::kSceneFingerprint, sha);
        }
    }
    for (const std::string& w : warnings)
        warn(w);
    if (!cameraError.empty()) throw py::value_error(cameraError);
    if (!ok) raiseError(error);
    if (deep) return py::cast(std::move(layers));
    return py::cast(Image::fromBuf(std::move(gbuf)));
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
        .def_property_readonly("materials",
                               [](const SceneHandle& h) {
                                   std::vector<std::string> names;
                                   for (const Material& mat : h.scene->materials)
                                       names.push_back(mat.name);
                                   return names;
                               })
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
             "fps"_a = 24.0, "animation"_a = py::none(),
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
          "lookat"_a = py::none(), "fov"_a = 0.0, "size"_a = std::pair<int, int>{1920, 1080},
          "frame_all"_a = false, "deep"_a = false, "max_layers"_a = GBufferParams{}.maxLayers,
          "time"_a = py::none(), "frame"_a = py::none(), "fps"_a = 24.0, "animation"_a = py::none(),
          "nthreads"_a = 0,
          R"(A flat G-buffer of the scene (dhdr-gbuffer): one primary ray per pixel, the channels of
docs/gbuffer.md as float32 by name, the header (camera matrices, name tables, Cryptomatte
manifests) in attributes. camera: a scene camera by name (default the first); lookat:
(eye, target[, up]) instead; fov: vertical degrees; size: (width, height); frame_all: move
the camera back until the scene fits. write_gbuffer() writes it in the contract's types.
deep=True (--deep): a DeepGBuffer, per pixel every surface up to the first opaque one, at
most max_layers (--max-layers) samples a pixel; deep='auto' (the tool's default): a
DeepGBuffer when a partly transparent surface is in view, else the flat Image.
A scene with animations is posed as dhdr-gbuffer --frame/--time poses it: at time seconds,
or frame / fps (frame 0, time 0, by default); animation: the one that plays, by name or
index, or 'all' (default the file's first, --animation). Its G-buffer has the motion layer
(motion.X, .Y, .Z, .W: Blender's Vector pass, pixels) and dhdr:animationTime, dhdr:fps and
dhdr:animation in its header. Each animated call poses its own copy of the scene
(docs/animation.md).)");

    m.def(
        "write_gbuffer",
        [](const std::string& path, const Image& gbuffer) {
            const ImageView v = view(gbuffer);
            // The contract's channels, then the motion layer of an animated frame.
            std::vector<std::string> names = gbuffer::channelNames();
            const bool motion = v.buf.spec().channelnames.size() == names.size() + 4;
            if (motion)
                names.insert(names.end(), std::begin(gbuffer::kMotion), std::end(gbuffer::kMotion));
            if (v.buf.spec().channelnames != names)
                throw py::value_error("gbuffer: not the channels of a dhdr G-buffer, in order "
                                      "(render_gbuffer's)");
            std::string error;
            {
                py::gil_scoped_release gil;
                ImageOutputOptions options;
                options.software = "dhdr python module (dhdr " DHDR_VERSION ")";
                ImageFileOutput file(path, options);
                if (!file.open(v.buf.spec(), gbufferChannelFormats(motion)) ||
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
