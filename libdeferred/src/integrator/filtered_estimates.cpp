#include "integrator/filtered_estimates.h"

#include "gi/bounce_light.h"
#include "gi/specular_indirect.h"

#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/denoise/denoise.h>
#include <dhdr/deferred/direct/ambient_occlusion.h>
#include <dhdr/deferred/direct/shadows.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/gi/probes.h>

namespace dhdr {

struct EstimateCarry::Rows {
    OIIO::ROI rows;                         // the frame's columns and rows they hold
    std::vector<std::vector<float>> planes; // FilteredEstimates::planes(), those rows of each
};

EstimateCarry::EstimateCarry() = default;
EstimateCarry::~EstimateCarry() = default;

std::vector<float*> FilteredEstimates::planes() {
    const size_t n = m_held.npixels();
    std::vector<float*> all;
    for (auto* pairs : {&m_diffuse, &m_specularRatio})
        for (std::vector<float>& sums : *pairs) {
            all.push_back(sums.data());
            all.push_back(sums.data() + n);
        }
    for (std::vector<float>* single :
         {&m_ao, &m_bounce, &m_specular[0], &m_specular[1], &m_specular[2]})
        if (!single->empty()) all.push_back(single->data());
    return all;
}

FilteredEstimates::FilteredEstimates(const GBufferView& view, const gbuffer::Layout& layout,
                                     OIIO::ROI held, OIIO::ROI read,
                                     const std::vector<Light>& lights, const LightingParams& params,
                                     const Visibility* shadowRays, const Visibility* aoRays,
                                     const TracedEstimates& traced, int nthreads,
                                     EstimateCarry* carry)
    : m_held(held), m_slot(lights.size(), -1) {
    // What the previous strip left, taken below if it fits; nothing is left for the next
    // unless this strip estimates.
    std::unique_ptr<EstimateCarry::Rows> previous = carry ? std::move(carry->rows) : nullptr;
    if (!params.denoise || view.deep()) return;
    std::vector<std::uint32_t> filtered;
    if (shadowRays && params.environmentSamples > 0)
        for (std::uint32_t i = 0; i < lights.size(); ++i)
            if (lights[i].type == LightType::Environment && lights[i].ibl &&
                !lights[i].ibl->sampler.empty()) {
                m_slot[i] = int(filtered.size());
                filtered.push_back(i);
            }
    const bool ao = aoRays && params.aoSamples > 0;
    const bool bouncing = traced.bounce && params.catcherBounceSamples > 0 && layout.objectId >= 0;
    const bool specular = traced.specular && params.specularSamples > 0;
    if (filtered.empty() && !ao && !bouncing && !specular) return;
    const size_t n = held.npixels();
    DenoiseGuide guide;
    guide.width = held.width();
    guide.height = held.height();
    guide.position.assign(n, glm::vec3(0.0f));
    guide.normal.assign(n, glm::vec3(0.0f));
    guide.object.assign(n, 0.0f);
    guide.surface.assign(n, 0);
    if (read.defined()) {
        guide.firstRow = std::clamp(read.ybegin, held.ybegin, held.yend) - held.ybegin;
        guide.endRow = std::clamp(read.yend, held.ybegin + guide.firstRow, held.yend) - held.ybegin;
    }
    // The glossy lobe of each pixel: its mirror direction and angular width (2α, the reflected
    // lobe being about twice the microfacets'; at least 0.02), for the specular sums.
    std::vector<glm::vec3> mirror(n, glm::vec3(0.0f, 0.0f, 1.0f));
    std::vector<float> lobeWidth(n, 1.0f);
    m_diffuse.assign(filtered.size(), std::vector<float>(2 * n, 0.0f));
    m_specularRatio.assign(filtered.size(), std::vector<float>(2 * n, 0.0f));
    if (specular)
        for (std::vector<float>& c : m_specular)
            c.assign(n, 0.0f);
    if (ao) m_ao.assign(n, 1.0f);
    if (bouncing) m_bounce.assign(n, 0.0f);
    // Where the bounce and the specular estimates exist: the filter skips the other pixels.
    std::vector<unsigned char> catcherPixels(bouncing ? n : 0), specularPixels(specular ? n : 0);
    // The rows the previous strip estimated too (the same frame's columns and estimates).
    const std::vector<float*> raw = planes();
    const size_t width = size_t(held.width());
    int carriedBegin = held.ybegin, carriedEnd = held.ybegin;
    if (previous && previous->rows.xbegin == held.xbegin && previous->rows.xend == held.xend &&
        previous->planes.size() == raw.size()) {
        carriedBegin = std::max(held.ybegin, previous->rows.ybegin);
        carriedEnd = std::max(carriedBegin, std::min(held.yend, previous->rows.yend));
        const size_t from = size_t(carriedBegin - previous->rows.ybegin) * width,
                     to = size_t(carriedBegin - held.ybegin) * width,
                     count = size_t(carriedEnd - carriedBegin) * width;
        for (size_t k = 0; k < raw.size(); ++k)
            std::copy_n(previous->planes[k].data() + from, count, raw[k] + to);
    }
    std::atomic<long long> shadowCount{0}, aoCount{0}, bounceCount{0}, specularCount{0};
    parallelRows(held.ybegin, held.yend, nthreads, [&](int64_t yy) {
        const int y = int(yy);
        const bool carried = y >= carriedBegin && y < carriedEnd;
        long long shadowLocal = 0, aoLocal = 0, bounceLocal = 0, specularLocal = 0;
        for (int x = held.xbegin; x < held.xend; ++x) {
            if (view.samples(x, y) == 0) continue;
            const size_t p = index(x, y);
            const ShadingPoint sp = view.at(x, y);
            guide.surface[p] = 1;
            guide.position[p] = sp.P;
            guide.normal[p] = sp.N;
            guide.object[p] = layout.objectId >= 0 ? view.channels(x, y)[layout.objectId] : 0.0f;
            // The seeds of a flat pixel's shading (lighting.cpp, deep sample 0).
            const LitPoint point{sp.surface, sp.P, sp.N, sp.V, sp.origin};
            const bool traceSpecular = specular && SpecularIndirect::traced(point, traced.probes);
            const SpecularLobe lobe{sp.V, sp.surface.alpha(),
                                    traceSpecular ? 0.0f : kOccluderAlbedo};
            mirror[p] = glm::reflect(-sp.V, sp.N);
            lobeWidth[p] = std::max(2.0f * lobe.alpha, 0.02f);
            if (bouncing) catcherPixels[p] = guide.object[p] == traced.catcher;
            if (specular) specularPixels[p] = traceSpecular;
            if (carried) continue;
            // With probes, a rough lobe's point takes nothing from environments (their
            // diffuse and its specular light come through the probes): no rays.
            const bool lit = !(traced.probes && sp.surface.roughness >= kProbeGlossyRoughness);
            for (size_t j = 0; j < filtered.size() && lit; ++j) {
                const EnvironmentVisibilitySums v = environmentVisibilitySums(
                    lights[filtered[j]], sp.origin, sp.N, &lobe,
                    sampleSeed(x, y, filtered[j], streamOf(SampleStream::Shadow)),
                    params.environmentSamples, *shadowRays, &shadowLocal);
                m_diffuse[j][p] = float(v.diffuse.seen);
                m_diffuse[j][n + p] = float(v.diffuse.total);
                m_specularRatio[j][p] = float(v.specular.seen);
                m_specularRatio[j][n + p] = float(v.specular.total);
            }
            if (ao)
                m_ao[p] = rayTracedOcclusion(
                    sp.origin, sp.N, sampleSeed(x, y, -1, streamOf(SampleStream::AmbientOcclusion)),
                    params.aoSamples, params.aoDistance, *aoRays, &aoLocal);
            if (bouncing && guide.object[p] == traced.catcher)
                m_bounce[p] = luminance(
                    diffuseAlbedo(sp.surface, std::max(glm::dot(sp.N, sp.V), 0.0f)) / kPi *
                    traced.bounce->irradianceAt(sp.origin, sp.N, x, y, 0,
                                                params.catcherBounceSamples, &bounceLocal));
            if (traceSpecular) {
                const glm::vec3 L = traced.specular->radiance(
                    point, x, y, 0, params.specularSamples, &specularLocal);
                for (int c = 0; c < 3; ++c)
                    m_specular[c][p] = L[c];
            }
        }
        shadowCount += shadowLocal;
        aoCount += aoLocal;
        bounceCount += bounceLocal;
        specularCount += specularLocal;
    });
    shadowRayCount = shadowCount;
    aoRayCount = aoCount;
    bounceRayCount = bounceCount;
    specularRayCount = specularCount;
    // The last rows, raw, for the next strip (whose halo above they are: dhdr-light's strips
    // overlap by 2 kDenoiseReach rows); rows it does not find there it traces.
    if (carry) {
        carry->rows = std::make_unique<EstimateCarry::Rows>();
        EstimateCarry::Rows& next = *carry->rows;
        next.rows = held;
        next.rows.ybegin = std::max(held.ybegin, held.yend - 2 * kDenoiseReach);
        const size_t from = size_t(next.rows.ybegin - held.ybegin) * width;
        for (const float* plane : raw)
            next.planes.emplace_back(plane + from, plane + n);
    }
    // Each pair of sums, and AO, keeps its own edges (its own variance guidance); the guide's
    // weights are shared.
    std::vector<DenoiseEstimate> estimates;
    for (std::vector<float>& sums : m_diffuse)
        estimates.push_back({&sums, 2});
    for (std::vector<float>& sums : m_specularRatio)
        estimates.push_back({&sums, 2, &mirror, &lobeWidth});
    if (ao) estimates.push_back({&m_ao, 1});
    if (bouncing) estimates.push_back({&m_bounce, 1, nullptr, nullptr, &catcherPixels});
    // The reflected scene, per channel, guided like the specular ratios by the lobe.
    if (specular)
        for (std::vector<float>& c : m_specular)
            estimates.push_back({&c, 1, &mirror, &lobeWidth, &specularPixels});
    atrousFilter(estimates, guide, nthreads);
}

EnvironmentVisibility FilteredEstimates::visibility(std::uint32_t light, int x, int y) const {
    const size_t p = index(x, y), slot = size_t(m_slot[light]);
    // The specular ratio counts occluders' light and may pass 1 (shadows.h).
    auto ratio = [&](const std::vector<float>& sums, float most) {
        const size_t n = sums.size() / 2;
        const float seen = sums[p], total = sums[n + p];
        return total > 0.0f ? std::clamp(seen / total, 0.0f, most) : 1.0f;
    };
    return {ratio(m_diffuse[slot], 1.0f), ratio(m_specularRatio[slot], INFINITY)};
}

float FilteredEstimates::ambientOcclusion(int x, int y) const {
    return std::clamp(m_ao[index(x, y)], 0.0f, 1.0f);
}

} // namespace dhdr
