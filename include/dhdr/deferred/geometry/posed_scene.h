// A scene across the frames or G-buffers of one run, and its ray caster (docs/animation.md):
// loaded once, posed at each moment (meshes that move as a whole traced as Embree instances,
// deformed ones refitted). dhdr-gbuffer and dhdr-probes pose it at each frame's time (with
// the frames either side for the motion layer); dhdr-light and light(scene=) pose it at the
// moment a G-buffer's header records, as dhdr-gbuffer posed it, so that shadow, AO and
// reflection rays see what the pixels show. Messages are returned, never printed.
#pragma once

#include <dhdr/deferred/gbuffer/gbuffer_time.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/scene/frame_motion.h>
#include <dhdr/deferred/scene/scene.h>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

OIIO_NAMESPACE_BEGIN
class ImageSpec;
OIIO_NAMESPACE_END

namespace dhdr {

class ScenePoser;

// Whose fault a failure to pose for a G-buffer is: the G-buffer's (a malformed moment, an
// animation the scene does not have: the wrong scene or G-buffer given) or the scene's (an
// animation it cannot play, a file that no longer loads, Embree).
enum class PoseFault { None, GBuffer, Scene };

// What posing for a G-buffer found: whether anything moved, what to say, what went wrong.
struct PoseReport {
    bool moved = false;                // the meshes or lights may differ from the last G-buffer's
    std::vector<std::string> notes;    // for -v
    std::vector<std::string> warnings; // always
    std::string error;                 // the whole message, naming the file at fault
    PoseFault fault = PoseFault::None;
};

// Which animations play when lighting G-buffer `gbufferName` of the scene file `scenePath`
// whose header records `moment` (readMoment): none without a moment or without animations;
// else the ones the G-buffer records, or for a file that does not record them dhdr-gbuffer's
// default, the scene's first. False with `report`'s error when one is not the scene's or
// cannot be played.
bool animationsAtMoment(const Scene& scene, const std::string& scenePath,
                        const std::string& gbufferName,
                        const std::optional<gbuffer::Moment>& moment, std::vector<int>& playing,
                        PoseReport& report);

// A copy of `scene` posed at time `t` with the animations `playing`, standing still there: its
// animations and instances gone, so that it is traced as its triangles lie (Scene.posed).
Scene stillCopy(const Scene& scene, const std::vector<int>& playing, double t);

class PosedScene {
public:
    PosedScene();
    ~PosedScene();
    PosedScene(const PosedScene&) = delete;
    PosedScene& operator=(const PosedScene&) = delete;

    // Loads the scene file `path`, forgetting what was held. False with loadScene's error.
    bool load(const std::string& path, const SceneOptions& options, std::string& error);
    // Holds a copy of `scene` (loaded from `path`, which messages name) instead.
    void hold(std::shared_ptr<const Scene> scene, const std::string& path);

    const std::string& path() const { return m_path; }
    Scene& scene() { return m_scene; }
    const Scene& scene() const { return m_scene; }
    // Built by the first pose; null before.
    const std::shared_ptr<RayCaster>& caster() const { return m_caster; }
    const std::vector<int>& playing() const { return m_playing; }
    bool animated() const { return !m_playing.empty(); }

    // Chooses the animations (`selection`: --animation's value, selectAnimations). False with
    // `error` (the file's animations listed) when the selection matches none.
    bool selectAnimations(const std::string& selection, std::string& error);

    // Plays the animations `indices` (playable ones of the scene; none: it stands still). The
    // meshes they move get a BVH that can be refitted: the ray caster is built again at the
    // next pose.
    void play(std::vector<int> indices);

    // Moves the scene to time `t` (when it is animated) and the ray caster with it (built the
    // first time). False with `error` when Embree fails.
    bool pose(double t, std::string& error);

    // The same, and when animated `motion` receives the scene at `before` and `after` (the
    // frames either side: (N ± 1) / fps, computed as frames so that a key's frame is on its
    // key), the camera of each given by `cameraOf`. Where that gives none (false), that half
    // of the motion layer is 0 (FrameMotion::hasPrevious, hasNext).
    bool pose(double before, double t, double after,
              const std::function<bool(const Scene&, Camera&)>& cameraOf,
              std::shared_ptr<FrameMotion>& motion, std::string& error);
    // The frames either side at t ± dt (a time, not a frame, is given).
    bool pose(double t, double dt, const std::function<bool(const Scene&, Camera&)>& cameraOf,
              std::shared_ptr<FrameMotion>& motion, std::string& error);

    // The box holding the scene at every key time of the playing animations and half-way
    // between keys (at most 1024 poses, taken evenly; the rest pose's when still): what
    // --frame-all frames once for every frame. Leaves the scene posed at one of those times.
    std::pair<glm::dvec3, glm::dvec3> animationBounds();

    // The moment a G-buffer (or a probe file) rendered at time `t` at `fps` records: none when
    // the scene stands still.
    std::optional<gbuffer::Moment> moment(double t, double fps) const;

    // What moves and how it is traced, for -v: "N meshes move: I as a whole (Embree
    // instances), R deformed (refitted)". Empty before the first pose or when nothing moves.
    std::string motionSummary() const;

    // Poses the scene for the G-buffer `gbufferName` whose header is `spec` (animationsAtMoment),
    // and refits or builds the ray caster. Another set of animations starts again from the
    // file (or the held scene), so that nothing the last set moved stays where it put it. What
    // is said once a run (a still file, the rest pose) is said for the first G-buffer only.
    bool poseFor(const std::string& gbufferName, const OIIO::ImageSpec& spec, PoseReport& report);

private:
    bool restart(std::string& error);

    std::string m_path;
    SceneOptions m_options;
    std::shared_ptr<const Scene> m_held; // hold()'s scene, which restart copies
    Scene m_scene;
    std::vector<int> m_playing; // the animations that play; empty: the scene does not move
    std::vector<int> m_moving;  // the meshes they move
    std::unique_ptr<ScenePoser> m_poser;
    std::shared_ptr<RayCaster> m_caster;
    bool m_touched = false;       // some mesh, camera or light is off its rest pose
    std::optional<double> m_time; // the time poseFor posed the scene at (none: the rest pose)
    bool m_warnedRest = false;    // the rest-pose warning, once a run
    bool m_saidStill = false;     // that the scene has no animations, once a run
};

} // namespace dhdr
