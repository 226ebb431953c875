#include <cstdio>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_camera.h>
#include <glm/gtc/constants.hpp>

namespace dhdr {

bool chooseCamera(const Scene& scene, const std::string& path, const CameraChoice& choice,
                  double aspect, Camera& camera, std::string& error,
                  std::vector<std::string>& notes, std::vector<std::string>& warnings,
                  Spelling spelling) {
    const bool keyword = spelling == Spelling::Keyword;
    if (choice.lookat) {
        camera = *choice.lookat;
    } else if (!scene.cameras.empty()) {
        const SceneCamera* chosen = &scene.cameras[0];
        if (!choice.name.empty()) {
            chosen = nullptr;
            std::string names;
            for (const SceneCamera& c : scene.cameras) {
                if (c.name == choice.name) chosen = &c;
                names += (names.empty() ? "" : ", ") + c.name;
            }
            if (!chosen) {
                error = path + ": no camera named '" + choice.name + "' (it has: " + names + ")";
                return false;
            }
        }
        if (!chosen->problem.empty()) {
            error = path + ": camera '" + chosen->name +
                    "' cannot be rendered from: " + chosen->problem;
            return false;
        }
        camera = chosen->camera;
        notes.push_back("camera '" + chosen->name + "'");
    } else if (choice.frameAll) {
        // Without a camera, one looking from the front and a little above, framed below.
        camera =
            Camera::lookAt({0.0, 0.34, 0.94}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, glm::radians(39.6));
    } else {
        error = path + ": the scene has no camera; give one with " +
                (keyword ? "lookat=, or frame_all=True" : "--lookat, or --frame-all");
        return false;
    }
    if (choice.fovDegrees > 0.0) {
        if (camera.orthographic)
            warnings.push_back(std::string(keyword ? "fov" : "--fov") +
                               " ignored: the camera is orthographic");
        else
            camera.yfov = glm::radians(choice.fovDegrees);
    }
    if (choice.frameAll) {
        const glm::dvec3 lo = choice.bounds ? choice.bounds->first : scene.boundsMin(),
                         hi = choice.bounds ? choice.bounds->second : scene.boundsMax();
        camera = frameBounds(lo, hi, camera, aspect);
        if (const std::string why = camera.problem(); !why.empty()) {
            char bounds[160];
            std::snprintf(bounds, sizeof bounds, "(%g, %g, %g) to (%g, %g, %g)", lo.x, lo.y, lo.z,
                          hi.x, hi.y, hi.z);
            error = path + ": " + (keyword ? "frame_all" : "--frame-all") +
                    " cannot frame the scene's bounds, " + bounds +
                    ": the camera that would fit them cannot be rendered from: " + why;
            return false;
        }
    }
    if (const std::string why = camera.problem(); !why.empty()) {
        error = path + ": the camera cannot be rendered from: " + why;
        return false;
    }
    notes.push_back(camera.orthographic
                        ? "orthographic camera, " + std::to_string(2.0 * camera.ymag) +
                              " units high"
                        : "perspective camera, vertical fov " +
                              std::to_string(glm::degrees(camera.yfov)) + " degrees");
    return true;
}

} // namespace dhdr
