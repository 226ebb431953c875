// dhdr-light's --scene across the G-buffers of a run: posed at the moment each G-buffer
// records (dhdr:animationTime and dhdr:animation, gbuffer_time.h) as dhdr-gbuffer posed it, so
// that shadow, AO and reflection rays see what the pixels show; a G-buffer that records no
// moment is lit against the file's rest pose, as before (docs/animation.md).
#pragma once

#include "../common/animated_scene.h"

#include <OpenImageIO/imageio.h>
#include <optional>
#include <string>
#include <vector>

namespace dhdr::app {

class Tool;

class PosedScene {
public:
    // Loads the scene file. False after the tool's error.
    bool load(const Tool& tool, const std::string& path, const SceneOptions& options);

    // Poses the scene for the G-buffer `gbuffer` whose header is `spec`, and refits or builds
    // the ray caster. `moved`: the scene's meshes or lights may differ from the last
    // G-buffer's (its lights must be taken again). False after the tool's error naming the
    // G-buffer (a malformed moment, an animation the scene does not have).
    bool poseFor(const Tool& tool, const std::string& gbuffer, const OIIO::ImageSpec& spec,
                 bool& moved);

    const Scene& scene() const { return m_loaded.scene; }
    const RayCaster* caster() const { return m_loaded.caster.get(); }

private:
    bool reload(const Tool& tool);

    std::string m_path;
    SceneOptions m_options;
    AnimatedScene m_loaded;
    bool m_touched = false;       // some mesh, camera or light is off its rest pose
    std::optional<double> m_time; // the time the scene is posed at (none: the rest pose)
    bool m_warnedRest = false;    // the rest-pose warning, once a run
    bool m_saidStill = false;     // that the scene has no animations, once a run
};

} // namespace dhdr::app
