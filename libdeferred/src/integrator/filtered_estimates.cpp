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
    size_t perLayer = 0;                    // planes a layer (layers: planes.size() / perLayer)
};

EstimateCarry::EstimateCarry() = default;
EstimateCarry::~EstimateCarry() = default;

std::vector<float*> FilteredEstimates::planes() {
    const size_t n = m_held.npixels();
    std::vector<float*> all;
    for (Planes& layer : m_layers) {
        for (auto* pairs : {&layer.diffuse, &layer.specularRatio})
            for (std::vector<float>& sums : *pairs) {
                all.push_back(sums.data());
                all.push_back(sums.data() + n);
            }
        for (std::vector<float>* single :
             {&layer.ao, &layer.bounce, &layer.specular[0], &layer.specular[1], &layer.specular[2]})
            if (!single->empty()) all.push_back(single->data());
    }
    return all;
}

struct FilteredEstimates::Guide {
    DenoiseGuide guide;
    // The glossy lobe of each pixel: its mirror direction and angular width (2α, the reflected
    // lobe being about twice the microfacets'; at least 0.02), for the specular sums.
    std::vector<glm::vec3> mirror;
    std::vector<float> lobeWidth;
    // Where the bounce and the specular estimates exist: the filter skips the other pixels.
    std::vector<unsigned char> catcherPixels, specularPixels;
};

// What one call estimates and filters with: its inputs, which estimates it makes, the guide
// of the filter and what else guides each estimate.
struct FilteredEstimates::Pass {
    Pass(const GBufferView& view, const gbuffer::Layout& layout, const std::vector<Light>& lights,
         const LightingParams& params, const Visibility* shadowRays, const Visibility* aoRays,
         const TracedEstimates& traced)
        : view(view), layout(layout), lights(lights), params(params), shadowRays(shadowRays),
          aoRays(aoRays), traced(traced) {}

    const GBufferView& view;
    const gbuffer::Layout& layout;
    const std::vector<Light>& lights;
    const LightingParams& params;
    const Visibility* shadowRays;
    const Visibility* aoRays;
    const TracedEstimates& traced;
    std::vector<std::uint32_t> filtered; // the environment lights estimated, in order
    bool ao = false, bouncing = false, specular = false;
    std::vector<Guide> guides; // per layer
    // The rows the previous strip estimated too (the same frame's columns and estimates).
    int carriedBegin = 0, carriedEnd = 0;

    bool any() const { return !filtered.empty() || ao || bouncing || specular; }
};

struct FilteredEstimates::Rays {
    long long shadow = 0, ao = 0, bounce = 0, specular = 0;
};

FilteredEstimates::FilteredEstimates(const GBufferView& view, const gbuffer::Layout& layout,
                                     OIIO::ROI held, OIIO::ROI read,
                                     const std::vector<Light>& lights,
                                     const std::vector<std::uint32_t>& infinite,
                                     const LightingParams& params, const Visibility* shadowRays,
                                     const Visibility* aoRays, const TracedEstimates& traced,
                                     int nthreads, EstimateCarry* carry)
    : m_held(held), m_slot(lights.size(), -1),
      m_sampleLayers(std::in_place, view, layout.coverage) {
    // What the previous strip left, taken below if it fits; nothing is left for the next
    // unless this strip estimates.
    std::unique_ptr<EstimateCarry::Rows> previous = carry ? std::move(carry->rows) : nullptr;
    if (!params.denoise) return;
    Pass pass(view, layout, lights, params, shadowRays, aoRays, traced);
    choose(pass, infinite);
    if (!pass.any()) return;
    allocate(pass, read);
    findDonors(view, layout, nthreads);
    const std::vector<float*> raw = planes();
    takeCarried(pass, previous.get(), raw);
    estimateRows(pass, nthreads);
    if (carry) leaveCarry(*carry, raw);
    filter(pass, nthreads);
}

// Which estimates this call makes: each environment light's shadow sums (one with a sampler,
// when its shadows are traced), the AO, a catcher's bounce light, the specular indirect light.
void FilteredEstimates::choose(Pass& pass, const std::vector<std::uint32_t>& infinite) {
    const LightingParams& params = pass.params;
    if (pass.shadowRays && params.environmentSamples > 0)
        for (const std::uint32_t i : infinite) {
            const Light& l = pass.lights[i];
            if (isEnvironment(l) && l.ibl && !l.ibl->sampler.empty()) {
                m_slot[i] = int(pass.filtered.size());
                pass.filtered.push_back(i);
            }
        }
    pass.ao = pass.aoRays && params.aoSamples > 0;
    pass.bouncing =
        pass.traced.bounce && params.catcherBounceSamples > 0 && pass.layout.objectId >= 0;
    pass.specular = pass.traced.specular && params.specularSamples > 0;
}

// The guides, the lobes and the planes of raw estimates of every layer some pixel of m_held
// reaches, every pixel of m_held's; the filter runs on the rows of `read` (undefined: all).
void FilteredEstimates::allocate(Pass& pass, OIIO::ROI read) {
    const OIIO::ROI& held = m_held;
    const size_t n = held.npixels();
    const int layers = m_sampleLayers->count(held.xbegin, held.xend, held.ybegin, held.yend);
    pass.guides.resize(size_t(layers));
    m_layers.resize(size_t(layers));
    for (int l = 0; l < layers; ++l) {
        Guide& g = pass.guides[size_t(l)];
        DenoiseGuide& guide = g.guide;
        guide.width = held.width();
        guide.height = held.height();
        guide.position.assign(n, glm::vec3(0.0f));
        guide.normal.assign(n, glm::vec3(0.0f));
        guide.object.assign(n, 0.0f);
        guide.surface.assign(n, 0);
        if (read.defined()) {
            guide.firstRow = std::clamp(read.ybegin, held.ybegin, held.yend) - held.ybegin;
            guide.endRow =
                std::clamp(read.yend, held.ybegin + guide.firstRow, held.yend) - held.ybegin;
        }
        g.mirror.assign(n, glm::vec3(0.0f, 0.0f, 1.0f));
        g.lobeWidth.assign(n, 1.0f);
        g.catcherPixels.assign(pass.bouncing ? n : 0, 0);
        g.specularPixels.assign(pass.specular ? n : 0, 0);
        Planes& planes = m_layers[size_t(l)];
        planes.diffuse.assign(pass.filtered.size(), std::vector<float>(2 * n, 0.0f));
        planes.specularRatio.assign(pass.filtered.size(), std::vector<float>(2 * n, 0.0f));
        if (pass.specular)
            for (std::vector<float>& c : planes.specular)
                c.assign(n, 0.0f);
        if (pass.ao) planes.ao.assign(n, 1.0f);
        if (pass.bouncing) planes.bounce.assign(n, 0.0f);
    }
}

// The rows the previous strip estimated too, copied from what it left (when it is of the same
// frame's columns and estimates): they are not traced again. A layer the previous strip did not
// have has no sample in those rows (they were the previous strip's too).
void FilteredEstimates::takeCarried(Pass& pass, const EstimateCarry::Rows* previous,
                                    const std::vector<float*>& raw) {
    const OIIO::ROI& held = m_held;
    pass.carriedBegin = pass.carriedEnd = held.ybegin;
    const size_t perLayer = raw.size() / m_layers.size();
    if (!previous || previous->rows.xbegin != held.xbegin || previous->rows.xend != held.xend ||
        previous->perLayer != perLayer)
        return;
    const size_t width = size_t(held.width());
    pass.carriedBegin = std::max(held.ybegin, previous->rows.ybegin);
    pass.carriedEnd = std::max(pass.carriedBegin, std::min(held.yend, previous->rows.yend));
    const size_t from = size_t(pass.carriedBegin - previous->rows.ybegin) * width,
                 to = size_t(pass.carriedBegin - held.ybegin) * width,
                 count = size_t(pass.carriedEnd - pass.carriedBegin) * width;
    for (size_t k = 0; k < std::min(raw.size(), previous->planes.size()); ++k)
        std::copy_n(previous->planes[k].data() + from, count, raw[k] + to);
}

// Every covered pixel's samples' guides and lobes, and their estimates unless carried.
void FilteredEstimates::estimateRows(Pass& pass, int nthreads) {
    std::atomic<long long> shadowCount{0}, aoCount{0}, bounceCount{0}, specularCount{0};
    parallelRows(m_held.ybegin, m_held.yend, nthreads, [&](int64_t yy) {
        const int y = int(yy);
        const bool carried = y >= pass.carriedBegin && y < pass.carriedEnd;
        Rays rays;
        for (int x = m_held.xbegin; x < m_held.xend; ++x) {
            const int samples = pass.view.samples(x, y);
            for (int k = 0; k < samples; ++k)
                if (m_sampleLayers->own(x, y, k)) estimateSample(pass, x, y, k, carried, rays);
        }
        shadowCount += rays.shadow;
        aoCount += rays.ao;
        bounceCount += rays.bounce;
        specularCount += rays.specular;
    });
    shadowRayCount = shadowCount;
    aoRayCount = aoCount;
    bounceRayCount = bounceCount;
    specularRayCount = specularCount;
}

// Sample k of pixel (x, y), with the seeds of its shading (shade_sample.cpp: sample k's
// streams; a flat pixel's are sample 0's).
void FilteredEstimates::estimateSample(Pass& pass, int x, int y, int k, bool carried, Rays& rays) {
    const LightingParams& params = pass.params;
    const TracedEstimates& traced = pass.traced;
    const size_t n = m_held.npixels(), p = index(x, y);
    const int layer = m_sampleLayers->layer(x, y, k);
    Guide& g = pass.guides[size_t(layer)];
    Planes& planes = m_layers[size_t(layer)];
    const ShadingPoint sp = pass.view.at(x, y, k);
    DenoiseGuide& guide = g.guide;
    guide.surface[p] = 1;
    guide.position[p] = sp.P;
    guide.normal[p] = sp.N;
    guide.object[p] =
        pass.layout.objectId >= 0 ? pass.view.channels(x, y, k)[pass.layout.objectId] : 0.0f;
    const LitPoint point{sp.surface, sp.P, sp.N, sp.V, sp.origin};
    const bool traceSpecular = pass.specular && SpecularIndirect::traced(point, traced.probes);
    const SpecularLobe lobe{sp.V, sp.surface.alpha(), traceSpecular ? 0.0f : kOccluderAlbedo};
    g.mirror[p] = glm::reflect(-sp.V, sp.N);
    g.lobeWidth[p] = std::max(2.0f * lobe.alpha, 0.02f);
    if (pass.bouncing) g.catcherPixels[p] = guide.object[p] == traced.catcher;
    if (pass.specular) g.specularPixels[p] = traceSpecular;
    if (carried) return;
    // With probes, a rough lobe's point takes nothing from environments (their diffuse and its
    // specular light come through the probes): no rays.
    const bool lit = !(traced.probes && sp.surface.roughness >= kProbeGlossyRoughness);
    for (size_t j = 0; j < pass.filtered.size() && lit; ++j) {
        const EnvironmentVisibilitySums v = environmentVisibilitySums(
            pass.lights[pass.filtered[j]], sp.origin, sp.N, &lobe,
            sampleSeed(x, y, pass.filtered[j], streamOf(SampleStream::Shadow, k)),
            params.environmentSamples, *pass.shadowRays, &rays.shadow);
        planes.diffuse[j][p] = float(v.diffuse.seen);
        planes.diffuse[j][n + p] = float(v.diffuse.total);
        planes.specularRatio[j][p] = float(v.specular.seen);
        planes.specularRatio[j][n + p] = float(v.specular.total);
    }
    if (pass.ao)
        planes.ao[p] = rayTracedOcclusion(
            sp.origin, sp.N, sampleSeed(x, y, -1, streamOf(SampleStream::AmbientOcclusion, k)),
            params.aoSamples, params.aoDistance, *pass.aoRays, &rays.ao);
    if (pass.bouncing && guide.object[p] == traced.catcher)
        planes.bounce[p] =
            luminance(diffuseAlbedo(sp.surface, std::max(glm::dot(sp.N, sp.V), 0.0f)) / kPi *
                      traced.bounce->irradianceAt(sp.origin, sp.N, x, y, k,
                                                  params.catcherBounceSamples, &rays.bounce));
    if (traceSpecular) {
        const glm::vec3 L =
            traced.specular->radiance(point, x, y, k, params.specularSamples, &rays.specular);
        for (int c = 0; c < 3; ++c)
            planes.specular[c][p] = L[c];
    }
}

// The last rows, raw, for the next strip (whose halo above they are: dhdr-light's strips
// overlap by 2 kDenoiseReach rows); rows it does not find there it traces.
void FilteredEstimates::leaveCarry(EstimateCarry& carry, const std::vector<float*>& raw) const {
    const OIIO::ROI& held = m_held;
    const size_t n = held.npixels(), width = size_t(held.width());
    carry.rows = std::make_unique<EstimateCarry::Rows>();
    EstimateCarry::Rows& next = *carry.rows;
    next.rows = held;
    next.rows.ybegin = std::max(held.ybegin, held.yend - 2 * kDenoiseReach);
    next.perLayer = raw.size() / m_layers.size();
    const size_t from = size_t(next.rows.ybegin - held.ybegin) * width;
    for (const float* plane : raw)
        next.planes.emplace_back(plane + from, plane + n);
}

// Layer by layer; each pair of sums, and AO, keeps its own edges (its own variance guidance);
// the guide's weights are shared.
void FilteredEstimates::filter(Pass& pass, int nthreads) {
    for (size_t l = 0; l < m_layers.size(); ++l) {
        Planes& planes = m_layers[l];
        Guide& g = pass.guides[l];
        std::vector<DenoiseEstimate> estimates;
        for (std::vector<float>& sums : planes.diffuse)
            estimates.push_back({&sums, 2});
        for (std::vector<float>& sums : planes.specularRatio)
            estimates.push_back({&sums, 2, &g.mirror, &g.lobeWidth});
        if (pass.ao) estimates.push_back({&planes.ao, 1});
        if (pass.bouncing)
            estimates.push_back({&planes.bounce, 1, nullptr, nullptr, &g.catcherPixels});
        // The reflected scene, per channel, guided like the specular ratios by the lobe.
        if (pass.specular)
            for (std::vector<float>& c : planes.specular)
                estimates.push_back({&c, 1, &g.mirror, &g.lobeWidth, &g.specularPixels});
        atrousFilter(estimates, g.guide, nthreads);
        g = Guide(); // freed as soon as its layer is filtered
    }
}

// Each sample of a pixel's other rays takes the estimates of the nearest own sample of the same
// layer and object in the pixel or its 8 neighbours (of any object when none is of its own; of
// its pixel's front sample's layer 0 when no neighbour reaches its layer): a ray a fraction of
// a pixel from its donor, on the same surface, where the filtered estimates are smooth.
void FilteredEstimates::findDonors(const GBufferView& view, const gbuffer::Layout& layout,
                                   int nthreads) {
    m_view = &view;
    if (!view.severalRays() || m_held.npixels() == 0) return;
    const SampleLayers& layers = *m_sampleLayers;
    auto position = [&](int x, int y, int k) {
        const float* g = view.channels(x, y, k) + layout.position;
        return glm::vec3(g[0], g[1], g[2]);
    };
    auto object = [&](int x, int y, int k) {
        return layout.objectId >= 0 ? view.channels(x, y, k)[layout.objectId] : 0.0f;
    };
    // Each held pixel's own samples, in order, and their layers: the only candidates (a few a
    // pixel of 16 rays; SampleLayers::layer counts through the pixel's samples).
    const size_t n = m_held.npixels();
    std::vector<std::uint32_t> ownFirst(n + 1, 0);
    std::vector<std::array<std::uint16_t, 2>> ownSample; // k, layer
    for (int y = m_held.ybegin; y < m_held.yend; ++y)
        for (int x = m_held.xbegin; x < m_held.xend; ++x) {
            for (int k = 0; k < view.samples(x, y); ++k)
                if (layers.own(x, y, k))
                    ownSample.push_back({std::uint16_t(k), std::uint16_t(layers.layer(x, y, k))});
            ownFirst[index(x, y) + 1] = std::uint32_t(ownSample.size());
        }
    m_donorBase = view.sampleIndex(m_held.xbegin, m_held.ybegin, 0);
    const int lastX = m_held.xend - 1, lastY = m_held.yend - 1;
    m_donors.assign(view.sampleIndex(lastX, lastY, view.samples(lastX, lastY)) - m_donorBase,
                    {kOwnPlace, kOwnPlace});
    parallelImageRows(m_held, nthreads, [&](OIIO::ROI rows) {
        for (int y = rows.ybegin; y < rows.yend; ++y)
            for (int x = m_held.xbegin; x < m_held.xend; ++x)
                for (int k = 0; k < view.samples(x, y); ++k) {
                    if (layers.own(x, y, k)) continue;
                    const int layer = layers.layer(x, y, k);
                    const glm::vec3 P = position(x, y, k);
                    const float id = object(x, y, k);
                    Place best{0, index(x, y)};
                    float bestDistance = INFINITY;
                    bool sameObject = false;
                    for (int ny = std::max(y - 1, m_held.ybegin); ny < std::min(y + 2, m_held.yend);
                         ++ny)
                        for (int nx = std::max(x - 1, m_held.xbegin);
                             nx < std::min(x + 2, m_held.xend); ++nx) {
                            const size_t q = index(nx, ny);
                            for (std::uint32_t i = ownFirst[q]; i < ownFirst[q + 1]; ++i) {
                                const int j = ownSample[i][0];
                                if (ownSample[i][1] != layer) continue;
                                const bool same = object(nx, ny, j) == id;
                                const float d = glm::length(position(nx, ny, j) - P);
                                if ((same && !sameObject) ||
                                    (same == sameObject && d < bestDistance)) {
                                    best = {size_t(layer), q};
                                    bestDistance = d;
                                    sameObject = same;
                                }
                            }
                        }
                    m_donors[view.sampleIndex(x, y, k) - m_donorBase] = {std::uint32_t(best.layer),
                                                                         std::uint32_t(best.pixel)};
                }
    });
}

FilteredEstimates::Place FilteredEstimates::placeOf(int x, int y, int k) const {
    if (!m_donors.empty() && !m_sampleLayers->own(x, y, k)) {
        const auto& donor = m_donors[m_view->sampleIndex(x, y, k) - m_donorBase];
        if (donor[0] != kOwnPlace) return {donor[0], donor[1]};
    }
    return {size_t(m_sampleLayers->layer(x, y, k)), index(x, y)};
}

EnvironmentVisibility FilteredEstimates::visibility(std::uint32_t light, int x, int y,
                                                    int k) const {
    const Place at = placeOf(x, y, k);
    const Planes& planes = m_layers[at.layer];
    const size_t p = at.pixel, slot = size_t(m_slot[light]);
    // The specular ratio counts occluders' light and may pass 1 (shadows.h).
    auto ratio = [&](const std::vector<float>& sums, float most) {
        const size_t n = sums.size() / 2;
        const float seen = sums[p], total = sums[n + p];
        return total > 0.0f ? std::clamp(seen / total, 0.0f, most) : 1.0f;
    };
    return {ratio(planes.diffuse[slot], 1.0f), ratio(planes.specularRatio[slot], INFINITY)};
}

float FilteredEstimates::ambientOcclusion(int x, int y, int k) const {
    const Place at = placeOf(x, y, k);
    return std::clamp(m_layers[at.layer].ao[at.pixel], 0.0f, 1.0f);
}

} // namespace dhdr
