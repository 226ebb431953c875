// Placing a probe volume's probes: the grid's spacing and origin, and each probe's move out of
// walls (DDGI's probe relocation, done once at the bake).
#include "gi/probe_placement.h"

#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/geometry/surface.h>
#include <dhdr/deferred/scene/scene.h>
#include <vector>

namespace dhdr {

namespace {

// Rays of the placement test.
constexpr int kPlacementRays = 128;

// Would a probe at `p` see the inside of a mesh, or stand too near a surface?
bool freeSpace(const RayCaster& caster, const glm::dvec3& p, double nearest, float backfaceLimit,
               const Scene& scene) {
    int back = 0;
    for (int i = 0; i < kPlacementRays; ++i) {
        Ray ray;
        ray.origin = p;
        ray.direction = glm::dvec3(sphericalFibonacci(i, kPlacementRays));
        const RayHit hit = caster.intersect(ray);
        if (!hit.hit) continue;
        if (hit.t < nearest) return false;
        back += surfaceGeometryAt(scene, ray, hit).backFace;
    }
    return back <= int(backfaceLimit * kPlacementRays);
}

// Probes along an axis of `extent` at most `spacing` apart with the outer ones kProbeInset
// spacings inside.
double probesAlong(double extent, double spacing) {
    return std::max(1.0, std::ceil(extent / spacing + 1.0 - 2.0 * kProbeInset - 1e-9));
}

// Their spacing, extent / (n − 1 + 2 kProbeInset) (at most `spacing`), or `spacing` for one.
double spacingAlong(double extent, double n, double spacing) {
    return n > 1.0 ? extent / (n - 1.0 + 2.0 * kProbeInset) : spacing;
}

// Candidate moves within half a cell of `spacing`, nearest first (a fixed order: the same
// choice on any machine).
std::vector<glm::dvec3> relocationMoves(const glm::dvec3& spacing) {
    std::vector<glm::dvec3> moves;
    for (int z = -4; z <= 4; ++z)
        for (int y = -4; y <= 4; ++y)
            for (int x = -4; x <= 4; ++x)
                if (x || y || z) moves.push_back(glm::dvec3(x, y, z) * (0.45 / 4.0) * spacing);
    std::stable_sort(moves.begin(), moves.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
        return glm::dot(a, a) < glm::dot(b, b);
    });
    return moves;
}

} // namespace

double probeSpacingFor(const glm::dvec3& extent, int maxProbes) {
    auto count = [&](double spacing) {
        double n = 1.0;
        for (int a = 0; a < 3; ++a)
            n *= probesAlong(extent[a], spacing);
        return n;
    };
    const double longest = std::max({extent.x, extent.y, extent.z});
    if (!(longest > 0.0)) return 1.0;
    // From the cube root of the volume per probe (the longest side's share where the box is
    // flat), up in 1 % steps until the grid fits: a fixed sequence, the same on any machine.
    double spacing =
        std::max(std::cbrt(std::max(extent.x, longest * 1e-3) * std::max(extent.y, longest * 1e-3) *
                           std::max(extent.z, longest * 1e-3) / maxProbes),
                 longest / kMaxProbesPerAxis);
    while (count(spacing) > maxProbes)
        spacing *= 1.01;
    return spacing;
}

bool layOutProbeGrid(const Scene& scene, const ProbeBakeParams& params, ProbeVolume& v,
                     std::string& error) {
    const glm::ivec3 counts = params.counts;
    const bool byCounts = counts.x > 0 || counts.y > 0 || counts.z > 0;
    const glm::dvec3 lo = scene.boundsMin(), hi = scene.boundsMax(), extent = hi - lo;
    const double spacing =
        params.spacing > 0.0 ? params.spacing : probeSpacingFor(extent, params.maxProbes);
    v = ProbeVolume{};
    for (int a = 0; a < 3; ++a) {
        if (byCounts) {
            v.counts[a] = counts[a];
            v.spacing[a] = spacingAlong(extent[a], counts[a], std::max(extent[a], 1e-3));
        } else {
            // In double, and refused past kMaxProbesPerAxis: a tiny spacing must neither overflow
            // an int nor be cut to a grid that no longer covers the scene.
            const double along = probesAlong(extent[a], spacing);
            if (!(along <= kMaxProbesPerAxis) || !(float(spacing) > 0.0f)) {
                error =
                    "a spacing of " + std::to_string(spacing) + " gives " +
                    (along < 1e12 ? std::to_string((long long)along) : std::string("over 10^12")) +
                    " probes along " + "XYZ"[a] + " (at most " + std::to_string(kMaxProbesPerAxis) +
                    "): use a larger spacing or counts";
                return false;
            }
            v.counts[a] = int(along);
            v.spacing[a] = spacingAlong(extent[a], along, spacing);
        }
        v.origin[a] = lo[a] + 0.5 * (extent[a] - (v.counts[a] - 1) * v.spacing[a]);
    }
    v.rays = params.rays;
    const int n = v.probeCount();
    if (n > 1 << 20) {
        error = "too many probes (" + std::to_string(n) + "); use a larger spacing";
        return false;
    }
    return true;
}

void placeProbes(const Scene& scene, const RayCaster& caster, const ProbeBakeParams& params,
                 ProbeVolume& v, int nthreads) {
    const int n = v.probeCount();
    v.positions.assign(size_t(n), glm::vec3(0.0f));
    v.states.assign(size_t(n), ProbeState::Active);
    const double minSpacing = std::min({v.spacing.x, v.spacing.y, v.spacing.z});
    const double nearest = params.minDistance * minSpacing;
    const std::vector<glm::dvec3> moves = relocationMoves(v.spacing);
    parallelRows(0, n, nthreads, [&](int64_t p) {
        const glm::ivec3 g(int(p % v.counts.x), int(p / v.counts.x % v.counts.y),
                           int(p / (v.counts.x * v.counts.y)));
        const glm::dvec3 home = v.gridPoint(g);
        v.positions[size_t(p)] = glm::vec3(home);
        if (freeSpace(caster, home, nearest, params.backfaceLimit, scene)) return;
        v.states[size_t(p)] = ProbeState::Off;
        for (const glm::dvec3& m : moves)
            if (freeSpace(caster, home + m, nearest, params.backfaceLimit, scene)) {
                v.positions[size_t(p)] = glm::vec3(home + m);
                v.states[size_t(p)] = ProbeState::Relocated;
                return;
            }
    });
}

} // namespace dhdr
