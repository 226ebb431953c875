// Baking a probe volume: placing the probes, tracing their rays, bouncing the light.
#include "gi/probe_rays.h"

#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/core/octahedral.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/geometry/surface.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr {

namespace {

constexpr double kPiD = 3.14159265358979323846;
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
        back += surfaceAt(scene, ray, hit).backFace;
    }
    return back <= int(backfaceLimit * kPlacementRays);
}

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

// Probes along an axis of `extent` at most `spacing` apart with the outer ones kProbeInset
// spacings inside.
double probesAlong(double extent, double spacing) {
    return std::max(1.0, std::ceil(extent / spacing + 1.0 - 2.0 * kProbeInset - 1e-9));
}

// Their spacing, extent / (n − 1 + 2 kProbeInset) (at most `spacing`), or `spacing` for one.
double spacingAlong(double extent, double n, double spacing) {
    return n > 1.0 ? extent / (n - 1.0 + 2.0 * kProbeInset) : spacing;
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
                 longest / 256.0);
    while (count(spacing) > maxProbes)
        spacing *= 1.01;
    return spacing;
}

bool bakeProbes(const Scene& scene, const RayCaster& caster, const std::vector<Light>& lights,
                bool emissiveAreLights, const ProbeBakeParams& params, ProbeVolume& v,
                std::string& error, int nthreads) {
    const glm::ivec3 counts = params.counts;
    const bool byCounts = counts.x > 0 || counts.y > 0 || counts.z > 0;
    if (error = checkRanges(params, kProbeBakeParamTable); !error.empty()) return false;
    if ((byCounts && (glm::any(glm::lessThan(counts, glm::ivec3(1))) ||
                      glm::any(glm::greaterThan(counts, glm::ivec3(256))))) ||
        (!byCounts && !(params.spacing >= 0.0))) {
        error = "probe grid out of range (counts 1-256, spacing > 0)";
        return false;
    }
    if (scene.meshes.empty()) {
        error = "the scene has no geometry to place probes in";
        return false;
    }
    // The grid over the scene's bounds: its outer layers kProbeInset spacings inside them.
    const glm::dvec3 lo = scene.boundsMin(), hi = scene.boundsMax(), extent = hi - lo;
    const double spacing =
        params.spacing > 0.0 ? params.spacing : probeSpacingFor(extent, params.maxProbes);
    v = ProbeVolume{};
    for (int a = 0; a < 3; ++a) {
        if (byCounts) {
            v.counts[a] = counts[a];
            v.spacing[a] = spacingAlong(extent[a], counts[a], std::max(extent[a], 1e-3));
        } else {
            // In double, and refused past 256: a tiny spacing must neither overflow an int
            // nor be cut to a grid that no longer covers the scene.
            const double along = probesAlong(extent[a], spacing);
            if (!(along <= 256.0) || !(float(spacing) > 0.0f)) {
                error =
                    "a spacing of " + std::to_string(spacing) + " gives " +
                    (along < 1e12 ? std::to_string((long long)along) : std::string("over 10^12")) +
                    " probes along " + "XYZ"[a] + " (at most 256): use a larger spacing or counts";
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
    v.positions.assign(size_t(n), glm::vec3(0.0f));
    v.states.assign(size_t(n), ProbeState::Active);
    const double minSpacing = std::min({v.spacing.x, v.spacing.y, v.spacing.z});
    const double nearest = params.minDistance * minSpacing;
    // Candidate moves within half a cell, nearest first (a fixed order: the same choice on
    // any machine).
    std::vector<glm::dvec3> moves;
    for (int z = -4; z <= 4; ++z)
        for (int y = -4; y <= 4; ++y)
            for (int x = -4; x <= 4; ++x)
                if (x || y || z) moves.push_back(glm::dvec3(x, y, z) * (0.45 / 4.0) * v.spacing);
    std::stable_sort(moves.begin(), moves.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
        return glm::dot(a, a) < glm::dot(b, b);
    });
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

    // Each probe's rays, traced once: what they hit, and the light there that no bounce
    // changes (direct light with shadows, and emission no light stands for).
    const int R = params.rays;
    const float maxDistance = float(4.0 * glm::length(v.spacing));
    std::vector<glm::vec3> directions(static_cast<size_t>(R));
    for (int i = 0; i < R; ++i)
        directions[size_t(i)] = sphericalFibonacci(i, R);
    std::vector<ProbeRay> results(size_t(n) * size_t(R));
    std::vector<std::vector<GlossyContinuation>> glossy(static_cast<size_t>(n));
    const ProbeRayTracer tracer(scene, caster, lights, params, emissiveAreLights);
    parallelRows(0, n, nthreads, [&](int64_t p) {
        if (v.states[size_t(p)] == ProbeState::Off) return;
        for (int i = 0; i < R; ++i)
            results[size_t(p) * size_t(R) + size_t(i)] =
                tracer.trace(v.positions[size_t(p)], directions[size_t(i)], {p, i, R}, maxDistance,
                             glossy[size_t(p)]);
    });
    if (params.progress) params.progress(0.5f);

    // Bounces: each round's rays carry the fixed light plus the last round's irradiance at
    // their hits reflected diffusely; the maps are then rebuilt from the rays.
    const int wi = ProbeVolume::kIrradianceTexels + 2, wd = ProbeVolume::kDistanceTexels + 2;
    v.irradiance.assign(size_t(n) * size_t(wi * wi), glm::vec3(0.0f));
    v.distance.assign(size_t(n) * size_t(wd * wd), glm::vec2(0.0f));
    std::vector<glm::vec3> radiance(results.size());
    // The irradiance texels' cosine weights max(0, t·ωᵢ), the same for every probe and bounce:
    // per texel, the rays in its hemisphere in ray order, and the weights' sum.
    const int ni = ProbeVolume::kIrradianceTexels;
    struct TexelRay {
        int ray;
        double cosine;
    };
    std::vector<TexelRay> texelRays;
    std::vector<size_t> texelStart(size_t(ni * ni) + 1, 0);
    std::vector<double> texelWeight(size_t(ni * ni), 0.0);
    for (int k = 0; k < ni * ni; ++k) {
        const glm::vec3 t = texelDirection(k % ni, k / ni, ni);
        for (int i = 0; i < R; ++i) {
            const double c = std::max(0.0, double(glm::dot(t, directions[size_t(i)])));
            texelWeight[size_t(k)] += c;
            if (c > 0.0) texelRays.push_back({i, c});
        }
        texelStart[size_t(k) + 1] = texelRays.size();
    }
    // Until the irradiance converges (bounces 0), or the bounces asked for.
    const bool converge = params.bounces == 0;
    const int rounds = converge ? kProbeMaxBounces : params.bounces;
    double lastTotal = 0.0, lastStep = 0.0;
    v.bounces = 0;
    v.diffuse = params.diffuse;
    for (int bounce = 0; bounce < rounds; ++bounce) {
        const ProbeVolume previous = v; // the last round's irradiance (zero at first)
        parallelRows(0, n, nthreads, [&](int64_t p) {
            for (int i = 0; i < R; ++i)
                radiance[size_t(p) * size_t(R) + size_t(i)] =
                    results[size_t(p) * size_t(R) + size_t(i)].radiance(
                        glossy[size_t(p)], bounce > 0 ? &previous : nullptr, directions[size_t(i)],
                        &caster);
        });
        parallelRows(0, n, nthreads, [&](int64_t p) {
            glm::vec3* irr = &v.irradiance[size_t(p) * size_t(wi * wi)];
            glm::vec2* dist = &v.distance[size_t(p) * size_t(wd * wd)];
            const ProbeRay* rr = &results[size_t(p) * size_t(R)];
            const glm::vec3* L = &radiance[size_t(p) * size_t(R)];
            if (v.states[size_t(p)] == ProbeState::Off) return;
            // E(n) = π Σ L cos⁺ / Σ cos⁺: the cosine-weighted mean radiance times π, exact for
            // a uniform surround (DDGI's normalisation); sums in double in ray order.
            for (int y = 0; y < ni; ++y)
                for (int x = 0; x < ni; ++x) {
                    const size_t k = size_t(y * ni + x);
                    glm::dvec3 sum(0.0);
                    for (size_t j = texelStart[k]; j < texelStart[k + 1]; ++j)
                        sum += glm::dvec3(L[texelRays[j].ray]) * texelRays[j].cosine;
                    const double weight = texelWeight[k];
                    irr[(y + 1) * wi + x + 1] =
                        weight > 0.0 ? glm::vec3(kPiD * sum / weight) : glm::vec3(0.0f);
                }
            fillBorders(irr, ni);
            if (bounce > 0) return; // distances do not change between bounces
            // Mean distance and mean squared distance under a sharp cosine lobe: the mean of
            // squares, not the square of the mean (the variance is their difference).
            const int nd = ProbeVolume::kDistanceTexels;
            for (int y = 0; y < nd; ++y)
                for (int x = 0; x < nd; ++x) {
                    const glm::vec3 t = texelDirection(x, y, nd);
                    double sum = 0.0, sum2 = 0.0, weight = 0.0;
                    for (int i = 0; i < R; ++i) {
                        const double c = std::max(0.0, double(glm::dot(t, directions[size_t(i)])));
                        if (c <= 0.0) continue;
                        const double w = std::pow(c, kProbeDistanceSharpness);
                        const double d = rr[i].distance;
                        sum += w * d;
                        sum2 += w * d * d;
                        weight += w;
                    }
                    dist[(y + 1) * wd + x + 1] =
                        weight > 0.0 ? glm::vec2(float(sum / weight), float(sum2 / weight))
                                     : glm::vec2(maxDistance, maxDistance * maxDistance);
                }
            fillBorders(dist, nd);
        });
        v.bounces = bounce + 1;
        // The whole field's irradiance, summed in double in probe and texel order.
        double total = 0.0;
        for (const glm::vec3& e : v.irradiance)
            total += double(e.r) + double(e.g) + double(e.b);
        // Each bounce adds about r times what the last one added (r < 1: the scene's mean
        // albedo as the light sees it), so what the bounces to come would still add is
        // step · r / (1 − r): stop when that is within kProbeConvergence of the total.
        const double step = total - lastTotal;
        const double r = lastStep > 0.0 ? step / lastStep : 1.0;
        const bool converged = converge && bounce > 1 && r < 1.0 &&
                               std::abs(step) * r / (1.0 - r) <= kProbeConvergence * total;
        lastTotal = total;
        lastStep = step;
        if (params.progress)
            params.progress(converged ? 1.0f : 0.5f + 0.5f * float(bounce + 1) / float(rounds));
        if (converged) break;
    }
    return true;
}

} // namespace dhdr
