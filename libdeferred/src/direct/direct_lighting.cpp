#include "direct/direct_lighting.h"

#include <dhdr/deferred/lights/light.h>

namespace dhdr {

namespace {

glm::vec3 scaled(const glm::vec3& c, float v) {
    return v != 1.0f ? c * v : c;
}

} // namespace

void DirectLighting::add(std::uint32_t i, const LitPoint& p, const SeedKey& key, DirectTerms& lit,
                         DirectTerms* open, const EnvironmentVisibility* given,
                         long long* rays) const {
    const Light& light = m_lights[i];
    const DirectLightingOptions& o = m_options;
    if (isDomeLight(light) && !o.lightsAtInfinity) return;
    auto seed = [&] { return sampleSeed(key.a, key.b, std::int64_t(i), key.stream); };
    if (isEnvironment(light)) {
        if (!light.ibl) return;
        IblShading e =
            shadeEnvironment(light, p.surface, p.N, p.V, o.environmentSpecular, p.reflectionSpread);
        if (!o.environmentDiffuse) e.diffuse = glm::vec3(0.0f);
        if (p.specularFromProbes) e.specular = glm::vec3(0.0f);
        e.diffuse = scaled(e.diffuse, p.occlusion);
        e.specular = scaled(e.specular, p.occlusion);
        if (e.diffuse == glm::vec3(0.0f) && e.specular == glm::vec3(0.0f)) return;
        // The visible shares of the environment's diffuse and specular light, from the same
        // rays, scale the prefiltered results.
        EnvironmentVisibility v;
        const bool traced = given || (o.shadows && o.environmentSamples > 0);
        if (given) {
            v = *given;
        } else if (traced) {
            const SpecularLobe lobe{p.V, p.surface.alpha(),
                                    p.tracedSpecular ? 0.0f : kOccluderAlbedo};
            v = ratios(environmentVisibilitySums(light, p.origin, p.N, &lobe, seed(),
                                                 o.environmentSamples, *o.shadows, rays));
        }
        // Traced visibility is the occlusion AO stands in for: AO scales only untraced light.
        auto addTo = [&](DirectTerms& t, const EnvironmentVisibility& w) {
            const glm::vec3 d = scaled(e.diffuse, w.diffuse), sp = scaled(e.specular, w.specular);
            if (o.occludable && !traced) {
                t.ambient += d;
                t.environmentSpecular += sp;
            } else {
                t.direct += d + sp;
            }
        };
        addTo(lit, v);
        if (open) addTo(*open, EnvironmentVisibility{});
        return;
    }
    glm::vec3 c =
        shadeLight(light, p.surface, p.P, p.N, p.V, p.reflectionSpread, p.footprintRadius);
    if (isAmbient(light)) c = scaled(c, p.occlusion);
    if (c == glm::vec3(0.0f)) return;
    float v = 1.0f;
    if (given)
        v = given->diffuse;
    else if (!isAmbient(light) && o.shadows)
        v = lightVisibility(light, p.origin, p.N, seed(), o.shadowSamples, *o.shadows, rays);
    glm::vec3& litTerm = isAmbient(light) && o.occludable ? lit.ambient : lit.direct;
    litTerm += scaled(c, v);
    if (open) (isAmbient(light) && o.occludable ? open->ambient : open->direct) += c;
}

void DirectLighting::addAreaLights(const std::uint32_t* lights, size_t count, const LitPoint& p,
                                   const SeedKey& key, DirectTerms& lit, DirectTerms* open,
                                   long long* rays) const {
    if (!sharesBudget(count)) {
        for (size_t k = 0; k < count; ++k)
            add(lights[k], p, key, lit, open, nullptr, rays);
        return;
    }
    // The lights that bring anything, and their unshadowed values (per thread: no allocation
    // per pixel).
    thread_local std::vector<const Light*> chosen;
    thread_local std::vector<glm::vec3> unshadowed;
    chosen.clear();
    unshadowed.clear();
    for (size_t k = 0; k < count; ++k) {
        const Light& light = m_lights[lights[k]];
        const glm::vec3 c =
            shadeLight(light, p.surface, p.P, p.N, p.V, p.reflectionSpread, p.footprintRadius);
        if (c == glm::vec3(0.0f)) continue;
        chosen.push_back(&light);
        unshadowed.push_back(c);
        if (open) open->direct += c;
    }
    if (chosen.empty()) return;
    lit.direct +=
        sharedLightVisibility(chosen.data(), unshadowed.data(), chosen.size(), p.origin, p.N,
                              sampleSeed(key.a, key.b, kSharedShadowsLight, key.stream), budget(),
                              *m_options.shadows, rays);
}

DirectTerms DirectLighting::sum(const LitPoint& p, const SeedKey& key, const glm::vec3& emission,
                                long long* rays) const {
    DirectTerms t{emission};
    for (std::uint32_t i = 0; i < m_lights.size(); ++i)
        add(i, p, key, t, nullptr, nullptr, rays);
    return t;
}

} // namespace dhdr
