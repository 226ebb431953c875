#include <cmath>
#include <dhdr/tonemap/adaptation.h>

namespace dhdr {

std::vector<double> adaptLuminance(const std::vector<double>& metered,
                                   const AdaptationParams& params) {
    std::vector<double> adapted(metered.size());
    if (metered.empty()) return adapted;
    const double dt = 1.0 / params.fps;
    const double step = 1.0 - std::pow(params.rate, params.speed * dt);
    adapted[0] = metered[0];
    for (size_t i = 1; i < metered.size(); ++i)
        adapted[i] = adapted[i - 1] + (metered[i] - adapted[i - 1]) * step;
    return adapted;
}

} // namespace dhdr
