#include "baked_probes.h"

#include "../common/tool.h"

#include <chrono>
#include <dhdr/deferred/geometry/posed_scene.h>

namespace dhdr::app {

const ProbeVolume* BakedProbes::forFrame(const Tool& tool, const PosedScene& scene,
                                         const std::vector<Light>& lights, bool emissiveAreLights,
                                         DiffuseModel diffuse, bool moved) {
    if (m_ready && !moved) return &m_volume;
    m_ready = false;
    const auto t = std::chrono::steady_clock::now();
    ProbeBakeParams params; // dhdr-probes' defaults: a file it bakes lights the frame alike
    params.diffuse = diffuse;
    Progress progress(tool, "dhdr-light: baking probes");
    params.progress = [&](float f) { progress.update(f); };
    std::string error;
    if (!bakeProbes(scene.scene(), *scene.caster(), lights, emissiveAreLights, params, m_volume,
                    error, tool.threads())) {
        // The frame's direct light does not depend on them: it is still made, without them.
        tool.warn("--gi auto: the probes cannot be baked (" + error +
                  "); the frame is lit without indirect light, as with --gi direct");
        return nullptr;
    }
    roundAsStored(m_volume);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
    tool.info(std::to_string(m_volume.probeCount()) + " probes baked in " +
              std::to_string(int(ms)) + " ms");
    m_ready = true;
    return &m_volume;
}

} // namespace dhdr::app
