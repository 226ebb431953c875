// A scene across the frames of one run (dhdr-gbuffer, dhdr-light): loaded once, posed at each
// frame's time (meshes that move as a whole traced as Embree instances, deformed ones
// refitted), and for dhdr-gbuffer's motion layer the previous and next frames' positions kept
// (docs/animation.md).
#pragma once

#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dhdr::app {

struct AnimatedScene {
    std::string path;    // the scene file loaded
    bool failed = false; // its loading failed (and was reported)
    Scene scene;
    std::vector<int> playing; // the animations that play; empty: the scene does not move
    std::vector<int> moving;  // the meshes they move
    std::unique_ptr<ScenePoser> poser;
    std::shared_ptr<RayCaster> caster;

    bool animated() const { return !playing.empty(); }

    // Chooses the animations (`selection`: --animation's value) after loading. False with
    // `error` (the file's animations listed) when the selection matches none.
    bool selectAnimations(const std::string& selection, std::string& error);

    // Plays the animations `indices` (playable ones of the scene; none: it stands still). The
    // meshes they move get a BVH that can be refitted: the ray caster is built again at the
    // next pose.
    void play(std::vector<int> indices);

    // Moves the scene to time `t` (when it is animated) and the ray caster with it (built the
    // first time). False with `error` when Embree fails.
    bool pose(double t, std::string& error);

    // What moves and how it is traced, for -v: "N meshes move: I as a whole (Embree
    // instances), R deformed (refitted)". Empty before the first pose or when nothing moves.
    std::string motionSummary() const;

    // The same, and with animation `motion` receives the scene at t − dt and t + dt, the camera
    // of each given by `cameraOf` (false: it failed and said why).
    bool pose(double t, double dt, const std::function<bool(const Scene&, Camera&)>& cameraOf,
              std::shared_ptr<FrameMotion>& motion, std::string& error);
};

// The time of frame `frame` at `fps` frames a second: frame 0 is time 0, as Blender imports
// and exports glTF.
inline double frameTime(int frame, double fps) {
    return double(frame) / fps;
}

} // namespace dhdr::app
