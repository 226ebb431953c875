// Which camera renders a scene: dhdr-gbuffer's --camera, --lookat, --fov and --frame-all, in
// one place for the tool and the Python module's render_gbuffer.
#pragma once

#include <dhdr/common/param_table.h>
#include <dhdr/deferred/scene/camera.h>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dhdr {

struct Scene;

struct CameraChoice {
    std::string name;             // a scene camera by name; empty: the scene's first
    std::optional<Camera> lookat; // instead of the scene's cameras
    double fovDegrees = 0.0;      // > 0: the vertical field of view of a perspective camera
    bool frameAll = false;        // moved back until the scene's bounds fit the image
    // With frameAll: the box to fit instead of the posed scene's (PosedScene::animationBounds),
    // so that an animation's frames share one framing rather than breathing with the pose.
    std::optional<std::pair<glm::dvec3, glm::dvec3>> bounds;
};

// CameraChoice's field of view, and the option of dhdr-gbuffer and keyword of
// dhdr.render_gbuffer() that set it.
inline constexpr FloatParam<CameraChoice, double> kCameraFloatTable[] = {
    {"--fov",
     "fov",
     &CameraChoice::fovDegrees,
     {0.0, 180.0, false, true},
     "DEG",
     "vertical field of view in degrees; 0, the default: the scene camera's (39.6 with "
     "--lookat)"},
};

// The camera of `scene` (read from `path`, which messages name) for an image of `aspect`
// (width / height). False with an error naming the scene when there is none to use (no camera,
// an unknown name listing the scene's, one that cannot be rendered from). `notes` receives what
// the tool says with -v, `warnings` what it warns about; both name the options as `spelling`
// says (--lookat, or the module's lookat=).
bool chooseCamera(const Scene& scene, const std::string& path, const CameraChoice& choice,
                  double aspect, Camera& camera, std::string& error,
                  std::vector<std::string>& notes, std::vector<std::string>& warnings,
                  Spelling spelling = Spelling::Option);

} // namespace dhdr
