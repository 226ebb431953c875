#include "gi/specular_indirect.h"

#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/gi/probes.h>

namespace dhdr {

bool SpecularIndirect::applies(const LitPoint& p) {
    const float NdotV = glm::dot(p.N, p.V);
    if (!(NdotV > 0.0f)) return false;
    if (p.surface.transmission > 0.0f) return true;
    const glm::vec2 e = ggxAlbedoTerms(NdotV, p.surface.roughness);
    const glm::vec3 albedo =
        p.surface.lobeReflectance(e) + multipleScatteringAlbedo(p.surface, NdotV);
    return luminance(albedo) >= kSpecularIndirectAlbedo;
}

bool SpecularIndirect::traced(const LitPoint& p, bool probes) {
    return applies(p) && !(probes && p.surface.roughness >= kProbeGlossyRoughness);
}

glm::vec3 SpecularIndirect::radiance(const LitPoint& p, int x, int y, int k, int samples,
                                     long long* rays) const {
    const float NdotV = glm::dot(p.N, p.V);
    if (samples <= 0 || !(NdotV > 0.0f)) return glm::vec3(0.0f);
    glm::vec3 t, b;
    orthonormalBasis(p.N, t, b);
    const glm::vec3 Vlocal(glm::dot(p.V, t), glm::dot(p.V, b), NdotV);
    // The base's lobe, under its coat: the coat reflects environments only (shadeEnvironment).
    const PbrSurface base = p.surface.uncoated();
    const float alpha = base.alpha();
    const RotatedHammersley sequence(
        sampleSeed(x, y, -4, streamOf(SampleStream::SpecularIndirect, k)));
    const std::int64_t hits =
        std::int64_t(sampleSeed(x, y, -5, streamOf(SampleStream::SpecularIndirect, k)));
    glm::dvec3 sum(0.0);
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 h = sampleGgxVisibleNormal(
            Vlocal, alpha, sequence(std::uint32_t(i), std::uint32_t(samples)));
        const glm::vec3 H = glm::normalize(h.x * t + h.y * b + h.z * p.N);
        const glm::vec3 wi = 2.0f * glm::dot(p.V, H) * H - p.V;
        const float NdotL = glm::dot(p.N, wi);
        if (!(NdotL > 0.0f) || !(glm::dot(p.origin.Ng, wi) > 0.0f)) continue;
        const float NdotH = std::max(glm::dot(p.N, H), 0.0f);
        const float pdf = ggxVisibleNormalReflectionPdf(NdotV, NdotH, alpha);
        if (!(pdf > 0.0f)) continue;
        const glm::vec3 f = specularBrdf(base, p.N, p.V, wi);
        const Ray ray{glm::dvec3(offsetRayOrigin(p.origin, wi)), glm::dvec3(wi)};
        const glm::vec3 L =
            m_hits.trace(ray, SeedKey{hits, i, streamOf(SampleStream::BounceShadow, k)}, rays);
        sum += glm::dvec3(f * (NdotL / pdf) * L);
    }
    const glm::vec3 L(sum / double(samples));
    return p.surface.coated() ? L * (1.0f - p.surface.coatBlend(p.V)) : L;
}

} // namespace dhdr
