#include "posed_scene.h"

#include "../common/tool.h"

#include <dhdr/deferred/gbuffer/gbuffer_time.h>

namespace dhdr::app {

bool PosedScene::load(const Tool& tool, const std::string& path, const SceneOptions& options) {
    m_path = path;
    m_options = options;
    if (!reload(tool)) return false;
    for (const std::string& warning : m_loaded.scene.warnings)
        tool.info(path + ": " + warning);
    return true;
}

bool PosedScene::reload(const Tool& tool) {
    m_loaded = AnimatedScene{};
    m_loaded.path = m_path;
    m_touched = false;
    m_time.reset();
    std::string error;
    if (!loadScene(m_path, m_loaded.scene, error, m_options)) {
        tool.fail(error);
        return false;
    }
    return true;
}

bool PosedScene::poseFor(const Tool& tool, const std::string& gbuffer, const OIIO::ImageSpec& spec,
                         bool& moved) {
    moved = false;
    std::optional<gbuffer::Moment> moment;
    std::string error;
    if (!gbuffer::readMoment(spec, moment, error)) {
        tool.fail(gbuffer + ": " + error);
        return false;
    }
    const std::vector<Animation> none;
    const Scene& scene = m_loaded.scene;
    const std::vector<Animation>& animations = scene.rig ? scene.rig->animations : none;
    // What plays: nothing without a moment; else what the G-buffer says played, or for a file
    // that does not say, dhdr-gbuffer's default, the scene's first animation.
    std::vector<int> playing;
    if (moment && animations.empty()) {
        // A still file for an animated G-buffer (a proxy, the shot's set alone): one pose to
        // light against, whatever the time.
        if (!m_saidStill)
            tool.info(gbuffer + ": " + m_path + " has no animations: lit against its one pose");
        m_saidStill = true;
    } else if (!moment) {
        if (!animations.empty() && !m_warnedRest) {
            tool.warn(gbuffer + ": records no animation time (" + gbuffer::kAnimationTime +
                      "): shadows and reflections see the rest pose of " + m_path);
            m_warnedRest = true;
        }
    } else if (moment->animations) {
        playing = *moment->animations;
    } else if (!animations.empty()) {
        playing = {0};
        tool.info(gbuffer + ": does not record its animations (" + gbuffer::kAnimation +
                  "); playing the scene's first");
    }
    for (const int a : playing) {
        if (size_t(a) >= animations.size()) {
            std::string names;
            for (size_t i = 0; i < animations.size(); ++i)
                names += (i ? ", " : "") + std::to_string(i) + " '" + animations[i].name + "'";
            tool.fail(gbuffer + ": rendered with animation " + std::to_string(a) + ", which " +
                      m_path + " does not have (it has: " + names +
                      "): is it the scene the G-buffer was rendered from?");
            return false;
        }
        if (!animations[size_t(a)].problem.empty()) {
            tool.fail(m_path + ": animation '" + animations[size_t(a)].name +
                      "' cannot be played: " + animations[size_t(a)].problem);
            return false;
        }
    }
    // Another set of animations (or none) starts again from the file, so that nothing the
    // last set moved stays where it put it.
    if (playing != m_loaded.playing || !m_loaded.caster) {
        if (m_touched && !reload(tool)) return false;
        m_loaded.play(playing);
        moved = true;
    }
    if (m_loaded.animated() && (!m_time || *m_time != moment->time)) {
        m_time = moment->time;
        m_touched = true;
        moved = true;
        tool.info(gbuffer + ": the scene posed at " + std::to_string(moment->time) + " s");
    }
    // Poses and refits (or builds the caster: the first G-buffer, or new animations).
    if (moved && !m_loaded.pose(m_time.value_or(0.0), error)) {
        tool.fail(m_path + ": " + error);
        return false;
    }
    return true;
}

} // namespace dhdr::app
