#include "animated_scene.h"

#include <algorithm>

namespace dhdr::app {

bool AnimatedScene::selectAnimations(const std::string& selection, std::string& error) {
    const std::vector<Animation> none;
    const std::vector<Animation>& animations = scene.rig ? scene.rig->animations : none;
    std::vector<int> chosen;
    if (!dhdr::selectAnimations(animations, selection, chosen, error)) return false;
    play(std::move(chosen));
    return true;
}

void AnimatedScene::play(std::vector<int> indices) {
    playing = scene.rig ? std::move(indices) : std::vector<int>{};
    moving.clear();
    poser.reset();
    caster.reset();
    if (!animated()) return;
    moving = scene.rig->movingMeshes(playing);
    poser = std::make_unique<ScenePoser>(scene, playing);
}

bool AnimatedScene::pose(double t, double dt,
                         const std::function<bool(const Scene&, Camera&)>& cameraOf,
                         std::shared_ptr<FrameMotion>& motion, std::string& error) {
    motion.reset();
    if (animated()) {
        // The frames around this one first, then this one, which the frame is rendered in.
        auto frame = std::make_shared<FrameMotion>();
        poser->pose(t - dt);
        if (!cameraOf(scene, frame->previousCamera)) return false;
        for (const Mesh& m : scene.meshes)
            frame->previous.push_back(m.positions);
        poser->pose(t + dt);
        if (!cameraOf(scene, frame->nextCamera)) return false;
        for (const Mesh& m : scene.meshes)
            frame->next.push_back(m.positions);
        motion = frame;
    }
    return pose(t, error);
}

bool AnimatedScene::pose(double t, std::string& error) {
    if (animated()) poser->pose(t);
    if (!caster) {
        caster = std::make_shared<RayCaster>(scene, moving);
    } else if (!caster->updateMeshes(moving)) {
        error = caster->error();
        return false;
    }
    if (!caster->ok()) {
        error = caster->error();
        return false;
    }
    return true;
}

std::string AnimatedScene::motionSummary() const {
    if (!caster || moving.empty()) return {};
    size_t instances = 0;
    for (const int i : moving)
        instances += caster->instanced(i) ? 1 : 0;
    return std::to_string(moving.size()) +
           (moving.size() == 1 ? " mesh moves: " : " meshes move: ") + std::to_string(instances) +
           " as a whole (Embree instances), " + std::to_string(moving.size() - instances) +
           " deformed (refitted)";
}

} // namespace dhdr::app
