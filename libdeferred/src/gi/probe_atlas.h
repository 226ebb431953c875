// A probe's octahedral maps written from its rays (probe_bake.cpp): the irradiance texels as
// cosine-weighted sums of the rays' radiance, the distance moments under a sharp lobe, and the
// one-texel borders that make the bilinear lookup seamless.
#pragma once

#include <cstddef>
#include <glm/glm.hpp>
#include <vector>

namespace dhdr {

struct ProbeRay;

// The irradiance texels' cosine weights max(0, t·ωᵢ), the same for every probe and bounce:
// per texel, the rays in its hemisphere in ray order, and the weights' sum.
struct IrradianceTexelRays {
    struct TexelRay {
        int ray;
        double cosine;
    };
    std::vector<TexelRay> rays;
    std::vector<size_t> start;  // texel k's rays are rays[start[k]] up to rays[start[k + 1]]
    std::vector<double> weight; // per texel

    explicit IrradianceTexelRays(const std::vector<glm::vec3>& directions);
};

// One probe's bordered irradiance map from the radiance its rays bring (one per direction).
void writeIrradiance(glm::vec3* map, const glm::vec3* radiance, const IrradianceTexelRays& texels);

// One probe's bordered distance-moment map from its rays (`directions`'s); texels no ray
// reaches hold maxDistance's.
void writeDistanceMoments(glm::vec2* map, const ProbeRay* rays,
                          const std::vector<glm::vec3>& directions, float maxDistance);

} // namespace dhdr
