#include <algorithm>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/lights/environment.h>

namespace dhdr {

glm::vec3 environmentRadiance(const Light& light, const glm::vec3& d) {
    if (!light.ibl) return glm::vec3(0.0f);
    return light.ibl->levels[0].radiance(intoEnvironment(light, d)) * light.color * light.intensity;
}

IblShading shadeEnvironment(const Light& light, const PbrSurface& s, const glm::vec3& N,
                            const glm::vec3& V, IblSpecular method, float spread) {
    if (s.coated()) {
        // The coat's lobe is specular light (withCoat): it joins the base's specular part.
        const float b = s.coatBlend(V);
        IblShading r = shadeEnvironment(light, s.uncoated(), N, V, method, spread);
        const IblShading c =
            shadeEnvironment(light, s.coatLobe(), s.coat.normal, V, method, spread);
        r.diffuse *= 1.0f - b;
        r.specular = r.specular * (1.0f - b) + (c.diffuse + c.specular) * b;
        return r;
    }
    if (s.sheened()) {
        // KHR_materials_sheen over the base: the base's light × its albedo scaling, plus the
        // sheen lobe's share of the irradiance, sheenColor E_sheen(N·V) E / π (exact for a
        // uniform sky; the Charlie lobe is broad). It joins the diffuse part: AO and the
        // environment's diffuse visibility scale it.
        const float k = s.sheenScaling(N, V);
        IblShading r = shadeEnvironment(light, s.bare(), N, V, method, spread);
        const float NdotV = std::max(glm::dot(N, V), 1e-4f);
        r.diffuse = r.diffuse * k + diffuseAlbedo(s.sheenLobe(), NdotV) *
                                        light.ibl->irradiance(intoEnvironment(light, N)) *
                                        (light.color * light.intensity / kPi);
        r.specular *= k;
        return r;
    }
    IblShading r = shadeIbl(*light.ibl, s, intoEnvironment(light, N), intoEnvironment(light, V),
                            method, spread);
    const glm::vec3 k = light.color * light.intensity;
    r.diffuse *= k;
    r.specular *= k;
    return r;
}

glm::vec3 shadeAmbient(const Light& light, const PbrSurface& s, const glm::vec3& N,
                       const glm::vec3& V) {
    // The directional albedo: the specular lobe's from the albedo table, once and multiply
    // scattered; the diffuse layer's from its Fresnel transmission (multiple_scattering.h).
    const float NdotV = std::max(glm::dot(N, V), 1e-4f);
    const glm::vec2 e = ggxAlbedoTerms(NdotV, s.roughness);
    const glm::vec3 specular = s.lobeReflectance(e) + multipleScatteringAlbedo(s, NdotV);
    return light.color * light.intensity * (diffuseAlbedo(s, NdotV) + specular);
}

LightLiSample sampleEnvironment(const Light& light, glm::vec2 u) {
    LightLiSample s;
    if (!light.ibl || light.ibl->sampler.empty()) return s;
    glm::vec3 radiance;
    const glm::vec3 d = light.ibl->sampler.sample(u, s.pdf, radiance);
    s.wi = fromEnvironment(light, d);
    s.L = radiance * light.color * light.intensity;
    s.distance = INFINITY;
    return s;
}

} // namespace dhdr
