// A probe's octahedral maps written from its rays: irradiance and distance moments.
#include "gi/probe_atlas.h"

#include "gi/probe_rays.h"

#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/octahedral.h>
#include <dhdr/deferred/gi/probes.h>

namespace dhdr {

namespace {

constexpr double kPiD = 3.14159265358979323846;

// The one-texel border of an n × n octahedral map (irradiance or distance moments).
template <class T>
void fillBorders(T* map, int n) {
    for (int y = 0; y < n + 2; ++y)
        for (int x = 0; x < n + 2; ++x)
            if (x == 0 || y == 0 || x == n + 1 || y == n + 1) {
                const glm::ivec2 s = octBorderSource(x, y, n);
                map[y * (n + 2) + x] = map[s.y * (n + 2) + s.x];
            }
}

// The direction at the centre of interior texel (i, j) of an n × n octahedral map.
glm::vec3 texelDirection(int i, int j, int n) {
    return octDecode(
        {(float(i) + 0.5f) / float(n) * 2.0f - 1.0f, (float(j) + 0.5f) / float(n) * 2.0f - 1.0f});
}

} // namespace

IrradianceTexelRays::IrradianceTexelRays(const std::vector<glm::vec3>& directions) {
    const int ni = ProbeVolume::kIrradianceTexels, R = int(directions.size());
    start.assign(size_t(ni * ni) + 1, 0);
    weight.assign(size_t(ni * ni), 0.0);
    for (int k = 0; k < ni * ni; ++k) {
        const glm::vec3 t = texelDirection(k % ni, k / ni, ni);
        for (int i = 0; i < R; ++i) {
            const double c = std::max(0.0, double(glm::dot(t, directions[size_t(i)])));
            weight[size_t(k)] += c;
            if (c > 0.0) rays.push_back({i, c});
        }
        start[size_t(k) + 1] = rays.size();
    }
}

void writeIrradiance(glm::vec3* map, const glm::vec3* radiance, const IrradianceTexelRays& texels) {
    const int ni = ProbeVolume::kIrradianceTexels, wi = ni + 2;
    // E(n) = π Σ L cos⁺ / Σ cos⁺: the cosine-weighted mean radiance times π, exact for a
    // uniform surround (DDGI's normalisation); sums in double in ray order.
    for (int y = 0; y < ni; ++y)
        for (int x = 0; x < ni; ++x) {
            const size_t k = size_t(y * ni + x);
            glm::dvec3 sum(0.0);
            for (size_t j = texels.start[k]; j < texels.start[k + 1]; ++j)
                sum += glm::dvec3(radiance[texels.rays[j].ray]) * texels.rays[j].cosine;
            const double weight = texels.weight[k];
            map[(y + 1) * wi + x + 1] =
                weight > 0.0 ? glm::vec3(kPiD * sum / weight) : glm::vec3(0.0f);
        }
    fillBorders(map, ni);
}

void writeDistanceMoments(glm::vec2* map, const ProbeRay* rays,
                          const std::vector<glm::vec3>& directions, float maxDistance) {
    const int nd = ProbeVolume::kDistanceTexels, wd = nd + 2, R = int(directions.size());
    // Mean distance and mean squared distance under a sharp cosine lobe: the mean of squares,
    // not the square of the mean (the variance is their difference).
    for (int y = 0; y < nd; ++y)
        for (int x = 0; x < nd; ++x) {
            const glm::vec3 t = texelDirection(x, y, nd);
            double sum = 0.0, sum2 = 0.0, weight = 0.0;
            for (int i = 0; i < R; ++i) {
                const double c = std::max(0.0, double(glm::dot(t, directions[size_t(i)])));
                if (c <= 0.0) continue;
                const double w = std::pow(c, kProbeDistanceSharpness);
                const double d = rays[i].distance;
                sum += w * d;
                sum2 += w * d * d;
                weight += w;
            }
            map[(y + 1) * wd + x + 1] = weight > 0.0
                                            ? glm::vec2(float(sum / weight), float(sum2 / weight))
                                            : glm::vec2(maxDistance, maxDistance * maxDistance);
        }
    fillBorders(map, nd);
}

} // namespace dhdr
