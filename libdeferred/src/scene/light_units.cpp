#include <dhdr/deferred/scene/lights.h>

namespace dhdr {

void toRadiometricUnits(std::vector<Light>& lights) {
    for (Light& l : lights)
        // An environment's sun carries the image's units, as the environment does.
        if (l.type == LightType::Point || l.type == LightType::Spot ||
            (l.type == LightType::Directional && !l.environmentSun))
            l.intensity /= kLuminousEfficacy;
}

} // namespace dhdr
