#include <algorithm>
#include <cmath>
#include <dhdr/deferred/geometry/posed_scene.h>
#include <dhdr/deferred/scene/animation.h>
#include <dhdr/deferred/scene/scene_rig.h>

namespace dhdr {

namespace {

const std::vector<Animation>& animationsOf(const Scene& scene) {
    static const std::vector<Animation> none;
    return scene.rig ? scene.rig->animations : none;
}

// What animationsAtMoment says once a run: which of its once-a-run messages to give and which
// it gave.
struct OnceARun {
    bool sayStill = true, warnRest = true;
    bool saidStill = false, warnedRest = false;
};

// What plays: nothing without a moment; else what the G-buffer says played, or for a file that
// does not say, dhdr-gbuffer's default, the scene's first.
void choosePlaying(const std::vector<Animation>& animations, const std::string& scenePath,
                   const std::string& gbufferName, const std::optional<gbuffer::Moment>& moment,
                   std::vector<int>& playing, PoseReport& report, OnceARun& once) {
    if (moment && animations.empty()) {
        // A still file for an animated G-buffer (a proxy, the shot's set alone): one pose to
        // light against, whatever the time.
        if (once.sayStill)
            report.notes.push_back(gbufferName + ": " + scenePath +
                                   " has no animations: lit against its one pose");
        once.saidStill = true;
    } else if (!moment) {
        if (!animations.empty() && once.warnRest) {
            report.warnings.push_back(
                gbufferName + ": records no animation time (" + gbuffer::kAnimationTime +
                "): shadows and reflections see the rest pose of " + scenePath);
            once.warnedRest = true;
        }
    } else if (moment->animations) {
        playing = *moment->animations;
    } else {
        playing = {0};
        report.notes.push_back(gbufferName + ": does not record its animations (" +
                               gbuffer::kAnimation + "); playing the scene's first");
    }
}

// False with the report's error when an animation of `playing` is not the scene's or cannot be
// played.
bool checkPlaying(const std::vector<Animation>& animations, const std::string& scenePath,
                  const std::string& gbufferName, const std::vector<int>& playing,
                  PoseReport& report) {
    for (const int a : playing) {
        if (size_t(a) >= animations.size()) {
            std::string names;
            for (size_t i = 0; i < animations.size(); ++i)
                names += (i ? ", " : "") + std::to_string(i) + " '" + animations[i].name + "'";
            report.error = gbufferName + ": rendered with animation " + std::to_string(a) +
                           ", which " + scenePath + " does not have (it has: " + names +
                           "): is it the scene the G-buffer was rendered from?";
            report.fault = PoseFault::GBuffer;
            return false;
        }
        if (!animations[size_t(a)].problem.empty()) {
            report.error = scenePath + ": animation '" + animations[size_t(a)].name +
                           "' cannot be played: " + animations[size_t(a)].problem;
            report.fault = PoseFault::Scene;
            return false;
        }
    }
    return true;
}

bool choosePlaying(const Scene& scene, const std::string& scenePath, const std::string& gbufferName,
                   const std::optional<gbuffer::Moment>& moment, std::vector<int>& playing,
                   PoseReport& report, OnceARun& once) {
    playing.clear();
    const std::vector<Animation>& animations = animationsOf(scene);
    choosePlaying(animations, scenePath, gbufferName, moment, playing, report, once);
    return checkPlaying(animations, scenePath, gbufferName, playing, report);
}

} // namespace

bool animationsAtMoment(const Scene& scene, const std::string& scenePath,
                        const std::string& gbufferName,
                        const std::optional<gbuffer::Moment>& moment, std::vector<int>& playing,
                        PoseReport& report) {
    OnceARun once;
    return choosePlaying(scene, scenePath, gbufferName, moment, playing, report, once);
}

Scene stillCopy(const Scene& scene, const std::vector<int>& playing, double t) {
    Scene out(scene);
    if (!playing.empty()) ScenePoser(out, playing).pose(t);
    // Standing still: traced as its triangles lie, no mesh an instance.
    out.rig.reset();
    for (Mesh& mesh : out.meshes)
        mesh.instance.reset();
    return out;
}

PosedScene::PosedScene() = default;
PosedScene::~PosedScene() = default;

bool PosedScene::load(const std::string& path, const SceneOptions& options, std::string& error) {
    m_path = path;
    m_options = options;
    m_held.reset();
    m_warnedRest = m_saidStill = false;
    return restart(error);
}

void PosedScene::hold(std::shared_ptr<const Scene> scene, const std::string& path) {
    m_path = path;
    m_held = std::move(scene);
    m_warnedRest = m_saidStill = false;
    std::string unused;
    restart(unused);
}

bool PosedScene::restart(std::string& error) {
    m_poser.reset();
    m_caster.reset();
    m_playing.clear();
    m_moving.clear();
    m_touched = false;
    m_time.reset();
    if (m_held) {
        m_scene = *m_held;
        return true;
    }
    m_scene = Scene{};
    return loadScene(m_path, m_scene, error, m_options);
}

bool PosedScene::selectAnimations(const std::string& selection, std::string& error) {
    std::vector<int> chosen;
    if (!dhdr::selectAnimations(animationsOf(m_scene), selection, chosen, error)) return false;
    play(std::move(chosen));
    return true;
}

void PosedScene::play(std::vector<int> indices) {
    m_playing = m_scene.rig ? std::move(indices) : std::vector<int>{};
    m_moving.clear();
    m_poser.reset();
    m_caster.reset();
    if (!animated()) return;
    m_moving = m_scene.rig->movingMeshes(m_playing);
    m_poser = std::make_unique<ScenePoser>(m_scene, m_playing);
}

bool PosedScene::pose(double t, double dt,
                      const std::function<bool(const Scene&, Camera&)>& cameraOf,
                      std::shared_ptr<FrameMotion>& motion, std::string& error) {
    return pose(t - dt, t, t + dt, cameraOf, motion, error);
}

bool PosedScene::pose(double before, double t, double after,
                      const std::function<bool(const Scene&, Camera&)>& cameraOf,
                      std::shared_ptr<FrameMotion>& motion, std::string& error) {
    motion.reset();
    if (animated()) {
        // The frames around this one first, then this one, which the frame is rendered in.
        auto frame = std::make_shared<FrameMotion>();
        m_poser->pose(before);
        frame->hasPrevious = cameraOf(m_scene, frame->previousCamera);
        for (const Mesh& m : m_scene.meshes)
            frame->previous.push_back(m.positions);
        m_poser->pose(after);
        frame->hasNext = cameraOf(m_scene, frame->nextCamera);
        for (const Mesh& m : m_scene.meshes)
            frame->next.push_back(m.positions);
        motion = frame;
    }
    return pose(t, error);
}

bool PosedScene::pose(double t, std::string& error) {
    if (animated()) m_poser->pose(t);
    if (!m_caster) {
        m_caster = std::make_shared<RayCaster>(m_scene, m_moving);
    } else if (!m_caster->updateMeshes(m_moving)) {
        error = m_caster->error();
        return false;
    }
    if (!m_caster->ok()) {
        error = m_caster->error();
        return false;
    }
    return true;
}

std::pair<glm::dvec3, glm::dvec3> PosedScene::animationBounds() {
    const std::pair<glm::dvec3, glm::dvec3> rest(m_scene.boundsMin(), m_scene.boundsMax());
    if (!animated()) return rest;
    // The poses at every key (between keys a pose lies close to its keys' for LINEAR motion)
    // and half-way between them (slerp and CUBICSPLINE's overshoot), at most kMaxBoundsPoses
    // taken evenly: the same box whatever frames a run renders.
    constexpr size_t kMaxBoundsPoses = 1024;
    std::vector<double> keys;
    for (const int a : m_playing)
        for (const AnimationSampler& s : m_scene.rig->animations[size_t(a)].samplers)
            keys.insert(keys.end(), s.times.begin(), s.times.end());
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    std::vector<double> times;
    for (size_t k = 0; k < keys.size(); ++k) {
        times.push_back(keys[k]);
        if (k + 1 < keys.size()) times.push_back(0.5 * (keys[k] + keys[k + 1]));
    }
    const size_t poses = std::min(times.size(), kMaxBoundsPoses);
    if (poses == 0) return rest;
    // The rest pose is left out: a frame never shows it where every mover holds its keys.
    std::pair<glm::dvec3, glm::dvec3> box(glm::dvec3(INFINITY), glm::dvec3(-INFINITY));
    for (size_t i = 0; i < poses; ++i) {
        const size_t at = poses == 1 ? 0 : i * (times.size() - 1) / (poses - 1);
        m_poser->pose(times[at]);
        box.first = glm::min(box.first, m_scene.boundsMin());
        box.second = glm::max(box.second, m_scene.boundsMax());
    }
    return box;
}

std::optional<gbuffer::Moment> PosedScene::moment(double t, double fps) const {
    if (!animated()) return std::nullopt;
    gbuffer::Moment moment;
    moment.time = t;
    moment.fps = fps;
    moment.animations = m_playing;
    return moment;
}

std::string PosedScene::motionSummary() const {
    if (!m_caster || m_moving.empty()) return {};
    size_t instances = 0;
    for (const int i : m_moving)
        instances += m_caster->instanced(i) ? 1 : 0;
    return std::to_string(m_moving.size()) +
           (m_moving.size() == 1 ? " mesh moves: " : " meshes move: ") + std::to_string(instances) +
           " as a whole (Embree instances), " + std::to_string(m_moving.size() - instances) +
           " deformed (refitted)";
}

bool PosedScene::poseFor(const std::string& gbufferName, const OIIO::ImageSpec& spec,
                         PoseReport& report) {
    report.moved = false;
    std::optional<gbuffer::Moment> moment;
    if (std::string error; !gbuffer::readMoment(spec, moment, error)) {
        report.error = gbufferName + ": " + error;
        report.fault = PoseFault::GBuffer;
        return false;
    }
    std::vector<int> playing;
    OnceARun once;
    once.sayStill = !m_saidStill;
    once.warnRest = !m_warnedRest;
    const bool chosen = choosePlaying(m_scene, m_path, gbufferName, moment, playing, report, once);
    m_saidStill = m_saidStill || once.saidStill;
    m_warnedRest = m_warnedRest || once.warnedRest;
    if (!chosen) return false;
    if (playing != m_playing || !m_caster) {
        if (m_touched && !restart(report.error)) {
            report.fault = PoseFault::Scene;
            return false;
        }
        play(playing);
        report.moved = true;
    }
    if (animated() && (!m_time || *m_time != moment->time)) {
        m_time = moment->time;
        m_touched = true;
        report.moved = true;
        report.notes.push_back(gbufferName + ": the scene posed at " +
                               std::to_string(moment->time) + " s");
    }
    // Poses and refits (or builds the caster: the first G-buffer, or new animations).
    std::string error;
    if (report.moved && !pose(m_time.value_or(0.0), error)) {
        report.error = m_path + ": " + error;
        report.fault = PoseFault::Scene;
        return false;
    }
    return true;
}

} // namespace dhdr
