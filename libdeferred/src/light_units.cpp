#include <dhdr/deferred/lights.h>

namespace dhdr {

void toRadiometricUnits(std::vector<Light>& lights) {
    for (Light& l : lights)
        if (l.type == LightType::Point || l.type == LightType::Spot ||
            l.type == LightType::Directional)
            l.intensity /= kLuminousEfficacy;
}

} // namespace dhdr
