// Baking a probe volume in the stages of a bake tool: placing the probes (probe_placement),
// tracing their rays once (probe_rays), then bouncing the light, each round's rays written
// into the octahedral maps (probe_atlas), until the irradiance converges.
#include "gi/probe_atlas.h"
#include "gi/probe_placement.h"
#include "gi/probe_rays.h"

#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/scene/scene.h>
#include <limits>

namespace dhdr {

namespace {

bool cancelled(const ProbeBakeParams& params) {
    return params.cancel && params.cancel->load(std::memory_order_relaxed);
}

// The parameters' ranges and the grid's, and a scene to place probes in.
bool checkBakeInputs(const Scene& scene, const ProbeBakeParams& params, std::string& error) {
    error = checkRanges(params, kProbeBakeParamTable);
    if (error.empty()) error = checkRanges(params, kProbeBakeFloatTable);
    if (error.empty()) error = checkRanges(params, kProbeGridTable);
    if (!error.empty()) return false;
    if (scene.meshes.empty()) {
        error = "the scene has no geometry to place probes in";
        return false;
    }
    return true;
}

// Each probe's rays, traced once: what they hit, and the light there that no bounce changes
// (direct light with shadows, and emission no light stands for).
struct ProbeTraces {
    std::vector<glm::vec3> directions;                   // the rays' of every probe
    std::vector<ProbeRay> rays;                          // per probe, one per direction
    std::vector<std::vector<GlossyContinuation>> glossy; // per probe
    float maxDistance = 0.0f;                            // a miss's distance
};

ProbeTraces traceProbeRays(const Scene& scene, const RayCaster& caster,
                           const std::vector<Light>& lights, bool emissiveAreLights,
                           const ProbeBakeParams& params, const ProbeVolume& v, int nthreads) {
    const int n = v.probeCount(), R = params.rays;
    ProbeTraces t;
    t.maxDistance = float(4.0 * glm::length(v.spacing));
    t.directions.resize(static_cast<size_t>(R));
    for (int i = 0; i < R; ++i)
        t.directions[size_t(i)] = sphericalFibonacci(i, R);
    t.rays.resize(size_t(n) * size_t(R));
    t.glossy.resize(static_cast<size_t>(n));
    const ProbeRayTracer tracer(scene, caster, lights, params, emissiveAreLights);
    parallelRows(0, n, nthreads, [&](int64_t p) {
        if (v.states[size_t(p)] == ProbeState::Off || cancelled(params)) return;
        for (int i = 0; i < R; ++i)
            t.rays[size_t(p) * size_t(R) + size_t(i)] =
                tracer.trace(v.positions[size_t(p)], t.directions[size_t(i)], {p, i, R},
                             t.maxDistance, t.glossy[size_t(p)]);
    });
    return t;
}

// The radiance each ray brings its probe at bounce `bounce`: the fixed light, plus after the
// first round what its hit reflects of `previous`'s irradiance.
void shadeProbeRays(const ProbeTraces& t, const ProbeVolume& previous, int bounce,
                    const RayCaster& caster, const ProbeBakeParams& params,
                    std::vector<glm::vec3>& radiance, int nthreads) {
    const int n = previous.probeCount(), R = int(t.directions.size());
    parallelRows(0, n, nthreads, [&](int64_t p) {
        if (cancelled(params)) return;
        for (int i = 0; i < R; ++i)
            radiance[size_t(p) * size_t(R) + size_t(i)] =
                t.rays[size_t(p) * size_t(R) + size_t(i)].radiance(
                    t.glossy[size_t(p)], bounce > 0 ? &previous : nullptr, t.directions[size_t(i)],
                    &caster);
    });
}

// The whole field's irradiance, summed in double in probe and texel order.
double irradianceTotal(const ProbeVolume& v) {
    double total = 0.0;
    for (const glm::vec3& e : v.irradiance)
        total += double(e.r) + double(e.g) + double(e.b);
    return total;
}

// Each bounce adds about r times what the last one added (r < 1: the scene's mean albedo as
// the light sees it), so what the bounces to come would still add is step · r / (1 − r):
// settled when that is within kProbeConvergence of the total.
class BounceConvergence {
public:
    // After bounce `bounce` (from 0), with the field's irradiance `total`.
    bool settled(double total, int bounce) {
        const double step = total - m_lastTotal;
        const double r = m_lastStep > 0.0 ? step / m_lastStep : 1.0;
        const bool settled =
            bounce > 1 && r < 1.0 && std::abs(step) * r / (1.0 - r) <= kProbeConvergence * total;
        m_lastTotal = total;
        m_lastStep = step;
        return settled;
    }

private:
    double m_lastTotal = 0.0, m_lastStep = 0.0;
};

// Bounces: each round's rays carry the fixed light plus the last round's irradiance at their
// hits reflected diffusely; the maps are then rebuilt from the rays. Until the irradiance
// converges (bounces 0), or the bounces asked for.
void bounceLight(const RayCaster& caster, const ProbeBakeParams& params, const ProbeTraces& t,
                 ProbeVolume& v, int nthreads) {
    const int n = v.probeCount(), R = params.rays;
    const int wi = ProbeVolume::kIrradianceTexels + 2, wd = ProbeVolume::kDistanceTexels + 2;
    v.irradiance.assign(size_t(n) * size_t(wi * wi), glm::vec3(0.0f));
    v.distance.assign(size_t(n) * size_t(wd * wd), glm::vec2(0.0f));
    std::vector<glm::vec3> radiance(t.rays.size());
    const IrradianceTexelRays texels(t.directions);
    const bool converge = params.bounces == 0;
    const int rounds = converge ? kProbeMaxBounces : params.bounces;
    BounceConvergence convergence;
    v.bounces = 0;
    v.diffuse = params.diffuse;
    for (int bounce = 0; bounce < rounds && !cancelled(params); ++bounce) {
        const ProbeVolume previous = v; // the last round's irradiance (zero at first)
        shadeProbeRays(t, previous, bounce, caster, params, radiance, nthreads);
        parallelRows(0, n, nthreads, [&](int64_t p) {
            if (v.states[size_t(p)] == ProbeState::Off) return;
            writeIrradiance(&v.irradiance[size_t(p) * size_t(wi * wi)],
                            &radiance[size_t(p) * size_t(R)], texels);
            if (bounce > 0) return; // distances do not change between bounces
            writeDistanceMoments(&v.distance[size_t(p) * size_t(wd * wd)],
                                 &t.rays[size_t(p) * size_t(R)], t.directions, t.maxDistance);
        });
        v.bounces = bounce + 1;
        const bool settled = convergence.settled(irradianceTotal(v), bounce);
        const bool converged = converge && settled;
        if (params.progress)
            params.progress(converged ? 1.0f : 0.5f + 0.5f * float(bounce + 1) / float(rounds));
        if (converged) break;
    }
}

// The irradiance values that are not finite; the distance moments' NaN → 0 and ±Inf →
// ±FLT_MAX, counted into `v.replaced` (a scene past float's range: squared distances overflow).
long long finiteMaps(ProbeVolume& v) {
    long long irradiance = 0;
    for (const glm::vec3& e : v.irradiance)
        irradiance += !std::isfinite(e.r + e.g + e.b);
    NonFiniteCount& n = v.replaced;
    n = NonFiniteCount();
    for (glm::vec2& d : v.distance)
        for (int c = 0; c < 2; ++c) {
            float& x = d[c];
            if (std::isnan(x)) {
                ++n.nan;
                x = 0.0f;
            } else if (std::isinf(x)) {
                ++(x > 0.0f ? n.positiveInf : n.negativeInf);
                x = std::copysign(std::numeric_limits<float>::max(), x);
            }
        }
    return irradiance;
}

} // namespace

bool bakeProbes(const Scene& scene, const RayCaster& caster, const std::vector<Light>& lights,
                bool emissiveAreLights, const ProbeBakeParams& params, ProbeVolume& v,
                std::string& error, int nthreads) {
    if (!checkBakeInputs(scene, params, error)) return false;
    if (!layOutProbeGrid(scene, params, v, error)) return false;
    auto interrupted = [&] {
        const bool stop = cancelled(params);
        if (stop) error = "interrupted";
        return stop;
    };
    placeProbes(scene, caster, params, v, nthreads);
    if (interrupted()) return false;
    const ProbeTraces traces =
        traceProbeRays(scene, caster, lights, emissiveAreLights, params, v, nthreads);
    if (interrupted()) return false;
    if (params.progress) params.progress(0.5f);
    bounceLight(caster, params, traces, v, nthreads);
    if (interrupted()) return false;
    if (const long long bad = finiteMaps(v); bad > 0) {
        // Black or float's largest would both misstate such light: refused.
        error = "the light reaching the probes is past float's range (" + std::to_string(bad) +
                " irradiance values not finite): lights of intensity near 3.4e38, or their sum";
        return false;
    }
    return true;
}

} // namespace dhdr
