#include <dhdr/deferred/lights/environment.h>

namespace dhdr {

glm::vec3 environmentRadiance(const Light& light, const glm::vec3& d) {
    if (!light.ibl) return glm::vec3(0.0f);
    return light.ibl->levels[0].radiance(intoEnvironment(light, d)) * light.color * light.intensity;
}

IblShading shadeEnvironment(const Light& light, const PbrSurface& s, const glm::vec3& N,
                            const glm::vec3& V) {
    IblShading r = shadeIbl(*light.ibl, s, intoEnvironment(light, N), intoEnvironment(light, V));
    const glm::vec3 k = light.color * light.intensity;
    r.diffuse *= k;
    r.specular *= k;
    return r;
}

glm::vec3 shadeAmbient(const Light& light, const PbrSurface& s, const glm::vec3&,
                       const glm::vec3&) {
    // The directional albedo approximated by its value at normal incidence,
    // c_diff (1 − F0) + F0.
    const glm::vec3 F0 = s.F0();
    return light.color * light.intensity * (s.diffuseColor() * (glm::vec3(1.0f) - F0) + F0);
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
