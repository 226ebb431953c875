#include "scene.h"

#include <dhdr/deferred/camera.h>
#include <dhdr/deferred/gbuffer.h>
#include <dhdr/deferred/gbuffer_render.h>
#include <dhdr/deferred/scene_camera.h>
#include <dhdr/deferred/scene_info.h>
#include <dhdr/io/image_output.h>
#include <dhdr/io/pixel_limit.h>
#include <glm/gtc/constants.hpp>
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

Image render(const SceneHandle& h, const std::string& camera, const py::object& lookat, double fov,
             std::pair<int, int> size, bool frameAll, bool deep, int nthreads) {
    if (deep)
        throw py::value_error("deep: the Python module renders flat G-buffers (dhdr-gbuffer "
                              "--deep writes deep ones)");
    GBufferParams params;
    params.width = size.first;
    params.height = size.second;
    if (params.width <= 0 || params.height <= 0)
        throw py::value_error("size: expected (width, height) of positive numbers");
    if (const std::string e = pixelLimitError(params.width, params.height); !e.empty())
        throw py::value_error("size: " + e);
    if (!(fov >= 0.0 && fov < 180.0)) throw py::value_error("fov: must be in (0, 180) degrees");
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
    Camera cam;
    std::string error;
    std::vector<std::string> notes, warnings;
    if (!chooseCamera(*h.scene, h.path, choice, double(params.width) / double(params.height), cam,
                      error, notes, warnings))
        throw py::value_error(error);
    for (const std::string& w : warnings)
        warn(w);
    OIIO::ImageBuf gbuf;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        const GBufferRenderer renderer(*h.scene, cam, params);
        if (!renderer.ok()) {
            error = h.path + ": " + renderer.error();
        } else {
            ok = renderer.render(gbuf, {}, nthreads);
            if (!ok) error = h.path + ": " + gbuf.geterror();
        }
        if (ok) {
            // What dhdr-gbuffer records: the scene file and its fingerprint (dhdr-light
            // compares it with --scene).
            gbuf.specmod().attribute("dhdr:source", h.path);
            if (const std::string sha = sceneFingerprint(h.path); !sha.empty())
                gbuf.specmod().attribute(gbuffer::kSceneFingerprint, sha);
        }
    }
    if (!ok) raiseError(error);
    return Image::fromBuf(std::move(gbuf));
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
        .def(
            "info", [](const SceneHandle& h) { return describeScene(*h.scene, h.path); },
            "What the scene holds, as dhdr-gbuffer --info prints it.")
        .def("__repr__", [](const SceneHandle& h) {
            return "dhdr.Scene('" + h.path + "', " + std::to_string(h.scene->meshes.size()) +
                   " meshes)";
        });

    m.def("render_gbuffer", &render, "scene"_a, py::kw_only(), "camera"_a = "",
          "lookat"_a = py::none(), "fov"_a = 0.0, "size"_a = std::pair<int, int>{1920, 1080},
          "frame_all"_a = false, "deep"_a = false, "nthreads"_a = 0,
          R"(A flat G-buffer of the scene (dhdr-gbuffer): one primary ray per pixel, the channels of
docs/gbuffer.md as float32 by name, the header (camera matrices, name tables, Cryptomatte
manifests) in attributes. camera: a scene camera by name (default the first); lookat:
(eye, target[, up]) instead; fov: vertical degrees; size: (width, height); frame_all: move
the camera back until the scene fits. write_gbuffer() writes it in the contract's types.)");

    m.def(
        "write_gbuffer",
        [](const std::string& path, const Image& gbuffer) {
            const ImageView v = view(gbuffer);
            if (v.buf.spec().channelnames != gbuffer::channelNames())
                throw py::value_error("gbuffer: not the channels of a dhdr G-buffer, in order "
                                      "(render_gbuffer's)");
            std::string error;
            {
                py::gil_scoped_release gil;
                ImageOutputOptions options;
                options.software = "dhdr python module (dhdr " DHDR_VERSION ")";
                ImageFileOutput file(path, options);
                if (!file.open(v.buf.spec(), gbufferChannelFormats()) ||
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
