// dhdr.Scene: a scene file loaded once (dhdr-gbuffer's and dhdr-light's --scene), rendered by
// render_gbuffer and traced by light(scene=...) for shadows, AO and emissive lights.
#pragma once

#include "py_image.h"

#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/scene/scene.h>
#include <memory>
#include <mutex>

namespace dhdr::python {

struct SceneHandle {
    std::string path;
    std::shared_ptr<Scene> scene;
    // Embree's acceleration structure, built by the first call that traces rays.
    struct Rays {
        std::once_flag once;
        std::unique_ptr<RayCaster> caster;
    };
    std::shared_ptr<Rays> rays = std::make_shared<Rays>();

    // The caster (built once, without the GIL); RuntimeError when Embree cannot be set up.
    const RayCaster& caster() const;
};

void bindScene(py::module_& m);

} // namespace dhdr::python
