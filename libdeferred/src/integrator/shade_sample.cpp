#include "integrator/shade_sample.h"

#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/direct/ambient_occlusion.h>
#include <dhdr/deferred/gi/probes.h>

namespace dhdr {

namespace {

// The angle the mirror directions of flat pixel (x, y) span: across and down, the angle
// between its mirror direction and its neighbour's (the next pixel, else the previous),
// the larger of the two; neighbours of another object or whose normal turns by more than 60°
// are another surface and do not count (0 when none does). Ray cones (Akenine-Möller et al.
// 2019) measure the same spread from the curvature; the G-buffer has the neighbours instead.
float reflectionSpread(const GBufferView& view, const gbuffer::Layout& layout, OIIO::ROI held,
                       int x, int y, const ShadingPoint& sp) {
    const glm::vec3 R = glm::reflect(-sp.V, sp.N);
    const float object = layout.objectId >= 0 ? view.channels(x, y)[layout.objectId] : 0.0f;
    float spread = 0.0f;
    for (const glm::ivec2 axis : {glm::ivec2(1, 0), glm::ivec2(0, 1)})
        for (const int side : {1, -1}) {
            const int qx = x + side * axis.x, qy = y + side * axis.y;
            if (qx < held.xbegin || qx >= held.xend || qy < held.ybegin || qy >= held.yend ||
                view.samples(qx, qy) == 0)
                continue;
            if (layout.objectId >= 0 && view.channels(qx, qy)[layout.objectId] != object) continue;
            const ShadingPoint q = view.at(qx, qy);
            if (!(glm::dot(q.N, sp.N) > 0.5f)) continue;
            const float c = std::clamp(glm::dot(R, glm::reflect(-q.V, q.N)), -1.0f, 1.0f);
            spread = std::max(spread, std::acos(c));
            break;
        }
    return spread;
}

} // namespace

LightReach::LightReach(const std::vector<Light>& lights) {
    for (const Light& l : lights) {
        const bool bounded = l.isLocal() && std::isfinite(l.range);
        x.push_back(l.position.x);
        y.push_back(l.position.y);
        z.push_back(l.position.z);
        range2.push_back(bounded ? l.range * l.range : INFINITY);
    }
}

struct SampleShader::At {
    int x, y, k;
    LightingStats& stats;
};

SampleShader::SampleShader(const ShadeSource& source, const LightingInputs& inputs,
                           const LightingParams& params, const ShadeSetup& setup,
                           const ShadeEstimators& estimators, const OutputPlan& plan,
                           const TileLightLists& tiles, OIIO::ROI frame)
    : m_source(source), m_inputs(inputs), m_params(params), m_setup(setup),
      m_estimators(estimators), m_filtered(*estimators.filtered), m_plan(plan), m_tiles(tiles),
      m_reach(inputs.lights), m_frame(frame) {}

ShadedSample SampleShader::shade(int x, int y, int k, LightingStats& stats, float* aovs) const {
    const ShadingPoint sp = m_source.view.at(x, y, k);
    stats.repairedNormals += sp.normalRepaired;
    const At at{x, y, k, stats};
    if (m_estimators.tracer) return pathTraced(sp, at, aovs);
    const float occlusion = ambientOcclusion(sp, at);
    // Lo = Le + Σ V_i L_i, in the order of the lights; with AO, the ambient terms are summed
    // apart and occluded at the end. The same sums without visibility (`open`) give a shadow
    // catcher its alpha. Emission: both start from Le.
    DirectTerms lit{sp.emission}, open{sp.emission};
    const LitPoint point = litPoint(sp, at);
    directLight(sp, point, at, lit, open);
    const glm::vec3 shaded = occluded(sp, lit, occlusion);
    const glm::vec3 indirect = probeIndirect(sp, point, occlusion);
    const glm::vec3 reflected = specularIndirect(point, at);
    const glm::vec3 Lo = shaded + indirect + reflected;
    if (aovs) m_plan.write(aovs, occlusion, indirect, reflected);
    if (onCatcher(at)) {
        const glm::vec4 c = shadowCatcher(sp, shaded, open, at);
        return {c, glm::vec3(1.0f - c.a)};
    }
    return premultiplied(sp, Lo);
}

// The reference: the path tracer's estimate plus the sample's emission; no AOV of its own.
ShadedSample SampleShader::pathTraced(const ShadingPoint& sp, const At& at, float* aovs) const {
    const glm::vec3 Lo =
        sp.emission + m_estimators.tracer->radiance({sp.surface, sp.P, sp.N, sp.V, sp.origin}, at.x,
                                                    at.y, at.k, &at.stats.pathRays);
    if (aovs) m_plan.writeNone(aovs);
    return premultiplied(sp, Lo);
}

// AO: the image given, the denoised estimate or traced here.
float SampleShader::ambientOcclusion(const ShadingPoint& sp, const At& at) const {
    if (m_setup.aoImage)
        return std::clamp(m_setup.aoImage->getchannel(at.x, at.y, 0, 0), 0.0f, 1.0f);
    if (m_filtered.filtersAO()) return m_filtered.ambientOcclusion(at.x, at.y, at.k);
    if (m_setup.rayTracedAO)
        return rayTracedOcclusion(
            sp.origin, sp.N,
            sampleSeed(at.x, at.y, -1, streamOf(SampleStream::AmbientOcclusion, at.k)),
            m_params.aoSamples, m_params.aoDistance, *m_inputs.visibility, &at.stats.aoRays);
    return 1.0f;
}

// The point as the lights see it: its pixel's reflection spread (flat pixels), and whether its
// glossy lobe's light is traced or comes from the probes.
LitPoint SampleShader::litPoint(const ShadingPoint& sp, const At& at) const {
    LitPoint point{
        sp.surface,
        sp.P,
        sp.N,
        sp.V,
        sp.origin,
        m_setup.footprint && !m_source.view.deep()
            ? reflectionSpread(m_source.view, m_source.layout, m_source.roi, at.x, at.y, sp)
            : 0.0f};
    const ProbeVolume* probes = m_setup.probes;
    point.tracedSpecular = m_estimators.specular && SpecularIndirect::traced(point, probes);
    point.specularFromProbes =
        probes && !point.tracedSpecular && sp.surface.roughness >= kProbeGlossyRoughness;
    point.occlusion = sp.occlusion;
    return point;
}

// Direct light: the lights of the pixel's tile and depth slice that reach the point (every
// light with bruteForce), in the order of the lights; where more area lights reach it than the
// budget of shadow rays allows them each, they share it (DirectLighting::addAreaLights).
void SampleShader::directLight(const ShadingPoint& sp, const LitPoint& point, const At& at,
                               DirectTerms& lit, DirectTerms& open) const {
    const SeedKey key{at.x, at.y, streamOf(SampleStream::Shadow, at.k)};
    LightingStats& stats = at.stats;
    // The lights to add and, apart, the area lights among them that reach the point (per
    // thread: no allocation per pixel).
    thread_local std::vector<std::uint32_t> candidates, area;
    candidates.clear();
    area.clear();
    if (m_params.bruteForce) {
        // The reference: every light's full evaluation, which is exactly zero where it does
        // not reach.
        const std::vector<Light>& lights = m_inputs.lights;
        for (std::uint32_t i = 0; i < lights.size(); ++i) {
            const bool reaches = m_reach.reaches(i, sp.P);
            stats.lightsReaching += reaches;
            candidates.push_back(i);
            if (reaches && lights[i].isArea()) area.push_back(i);
        }
        stats.lightEvaluations += (long long)lights.size();
    } else {
        const int px = at.x - m_frame.xbegin, py = at.y - m_frame.ybegin;
        const std::uint32_t slice = m_tiles.sliceBit(px, py, sp.depth);
        for (const TileLightLists::Entry& e : m_tiles.at(px, py)) {
            if (!(e.depthMask & slice)) continue;
            ++stats.lightEvaluations;
            // Out of range, the window is exactly zero: skip before reading more.
            if (!m_reach.reaches(e.light, sp.P)) continue;
            ++stats.lightsReaching;
            candidates.push_back(e.light);
            if (m_inputs.lights[e.light].isArea()) area.push_back(e.light);
        }
    }
    const DirectLighting& direct = m_estimators.direct;
    if (!direct.sharesBudget(area.size())) {
        for (const std::uint32_t i : candidates)
            addLight(i, point, key, at, lit, open);
        return;
    }
    for (const std::uint32_t i : candidates)
        if (!m_inputs.lights[i].isArea()) addLight(i, point, key, at, lit, open);
    direct.addAreaLights(area.data(), area.size(), point, key, lit, &open, &at.stats.shadowRays);
}

// Light i, shadowed into `lit` and unshadowed into `open`; with the denoiser, an environment's
// visibility is its filtered estimate.
void SampleShader::addLight(std::uint32_t i, const LitPoint& point, const SeedKey& key,
                            const At& at, DirectTerms& lit, DirectTerms& open) const {
    EnvironmentVisibility v;
    const bool given = m_filtered.filters(i);
    if (given) v = m_filtered.visibility(i, at.x, at.y, at.k);
    m_estimators.direct.add(i, point, key, lit, &open, given ? &v : nullptr, &at.stats.shadowRays);
}

// Ambient light and AO: the occludable terms scaled by AO and specular occlusion.
glm::vec3 SampleShader::occluded(const ShadingPoint& sp, const DirectTerms& lit,
                                 float occlusion) const {
    const float so = m_setup.aoActive ? specularOcclusion(std::max(glm::dot(sp.N, sp.V), 0.0f),
                                                          occlusion, sp.surface.roughness)
                                      : 1.0f;
    return lit.total(occlusion, so);
}

// Indirect light from the probes: the diffuse layer's (diffuseAlbedo × E / π, as for
// environments) and, where the probes bring it, the rough specular lobe's (specularAlbedo ×
// E / π, as the bake's hits reflect it); occluded by AO like the ambient terms.
glm::vec3 SampleShader::probeIndirect(const ShadingPoint& sp, const LitPoint& point,
                                      float occlusion) const {
    glm::vec3 indirect(0.0f);
    if (m_setup.probes) {
        const PbrSurface& s = sp.surface;
        indirect = m_setup.probes->reflectedAt(s.sheened() ? s.bare() : s, sp.P, sp.N, sp.V,
                                               point.specularFromProbes, m_inputs.visibility);
        // KHR_materials_sheen over the base, as for environments (shadeEnvironment).
        if (s.sheened())
            indirect = indirect * s.sheenScaling(sp.N, sp.V) +
                       m_setup.probes->reflectedAt(s.sheenLobe(), sp.P, sp.N, sp.V, false,
                                                   m_inputs.visibility);
        if (m_setup.aoActive) indirect *= occlusion;
        if (sp.occlusion != 1.0f) indirect *= sp.occlusion;
        if (sp.surface.coated()) indirect *= 1.0f - sp.surface.coatBlend(sp.V);
    }
    return indirect;
}

// The scene in the glossy lobe, traced (not occluded by AO: its rays see the occluders).
glm::vec3 SampleShader::specularIndirect(const LitPoint& point, const At& at) const {
    if (!point.tracedSpecular) return glm::vec3(0.0f);
    const glm::vec3 L =
        m_filtered.filtersSpecular()
            ? m_filtered.specularIndirect(at.x, at.y, at.k)
            : m_estimators.specular->radiance(point, at.x, at.y, at.k, m_params.specularSamples,
                                              &at.stats.specularRays);
    return point.occlusion != 1.0f ? L * point.occlusion : L;
}

bool SampleShader::onCatcher(const At& at) const {
    const int object = m_source.layout.objectId;
    return m_setup.catcherId > 0 && object >= 0 &&
           m_source.view.channels(at.x, at.y, at.k)[object] == m_setup.catcherId;
}

// A shadow catcher (Blender's convention): no colour of its own, and the share of light that
// shadows and AO take away, less what the objects bounce back onto it, as alpha.
glm::vec4 SampleShader::shadowCatcher(const ShadingPoint& sp, const glm::vec3& shaded,
                                      const DirectTerms& open, const At& at) const {
    const float bounce = catcherBounce(sp, at);
    const float unshadowed = luminance(open.total(1.0f, 1.0f));
    return glm::vec4(0.0f, 0.0f, 0.0f,
                     unshadowed > 0.0f
                         ? std::clamp(1.0f - (luminance(shaded) + bounce) / unshadowed, 0.0f, 1.0f)
                         : 0.0f);
}

// The luminance of the catcher's diffuse reflection of the bounce irradiance.
float SampleShader::catcherBounce(const ShadingPoint& sp, const At& at) const {
    if (m_filtered.filtersBounce()) return m_filtered.catcherBounce(at.x, at.y, at.k);
    if (!m_estimators.bounce) return 0.0f;
    return luminance(diffuseAlbedo(sp.surface, std::max(glm::dot(sp.N, sp.V), 0.0f)) / kPi *
                     m_estimators.bounce->irradianceAt(sp.origin, sp.N, at.x, at.y, at.k,
                                                       m_params.catcherBounceSamples,
                                                       &at.stats.bounceRays));
}

ShadedSample SampleShader::premultiplied(const ShadingPoint& sp, const glm::vec3& Lo) const {
    if (!m_source.view.deep()) return {glm::vec4(Lo, sp.coverage), glm::vec3(1.0f - sp.coverage)};
    const float a = sp.coverage;
    if (sp.surface.transmission <= 0.0f) return {glm::vec4(Lo * a, a), glm::vec3(1.0f - a)};
    const glm::vec3 behind =
        (1.0f - a) + a * transmittance(sp.surface, sp.N, sp.V) * sp.attenuation;
    return {glm::vec4(Lo * a, 1.0f - (behind.r + behind.g + behind.b) / 3.0f), behind, true};
}

} // namespace dhdr
