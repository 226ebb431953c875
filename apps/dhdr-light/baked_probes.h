// --gi auto's light probes (planProbes): baked in the run for the frames it lights, as
// dhdr-probes bakes them by default, once for a still scene under the same lights and again
// for each frame where the scene or its lights move (docs/gi.md, "Probes by default").
#pragma once

#include <dhdr/deferred/gi/probes.h>
#include <vector>

namespace dhdr {
class PosedScene;
}

namespace dhdr::app {

class Tool;

class BakedProbes {
public:
    // The probes of `scene` as posed for the frame, lit by `lights`; `moved`: the scene or
    // the lights are not those of the last bake. Null, after a warning, when they cannot be
    // baked (a scene past float's range): the frame is then lit without them.
    const ProbeVolume* forFrame(const Tool& tool, const PosedScene& scene,
                                const std::vector<Light>& lights, bool emissiveAreLights,
                                DiffuseModel diffuse, bool moved);

private:
    ProbeVolume m_volume;
    bool m_ready = false;
};

} // namespace dhdr::app
