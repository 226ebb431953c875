#include <dhdr/deferred/lights/light.h>

namespace dhdr {

namespace {

// One layer of a surface (no coat): the light family's own shading.
glm::vec3 shadeLayer(const Light& light, const PbrSurface& s, const glm::vec3& P,
                     const glm::vec3& N, const glm::vec3& V, float spread, float footprintRadius) {
    switch (light.type) {
    case LightType::Point:
    case LightType::Spot:
    case LightType::Directional:
        return shadePunctual(light, s, P, N, V, spread, footprintRadius);
    case LightType::Sphere:
    case LightType::Rectangle:
    case LightType::Mesh:
        return shadeAreaLight(light, s, P, N, V);
    case LightType::Ambient:
        return shadeAmbient(light, s, N, V);
    case LightType::Environment:
        break; // shadeEnvironment layers the coat itself
    }
    return glm::vec3(0.0f);
}

} // namespace

glm::vec3 shadeLight(const Light& light, const PbrSurface& s, const glm::vec3& P,
                     const glm::vec3& N, const glm::vec3& V, float spread, float footprintRadius) {
    if (light.type == LightType::Environment) {
        if (!light.ibl) return glm::vec3(0.0f);
        const IblShading e = shadeEnvironment(light, s, N, V);
        return e.diffuse + e.specular;
    }
    return withCoat(s, N, V, [&](const PbrSurface& layer, const glm::vec3& n) {
        return shadeLayer(light, layer, P, n, V, spread, footprintRadius);
    });
}

LightLiSample sampleLi(const Light& light, const glm::vec3& P, glm::vec2 u) {
    switch (light.type) {
    case LightType::Point:
    case LightType::Spot:
    case LightType::Directional:
        return samplePunctual(light, P, u);
    case LightType::Sphere:
    case LightType::Rectangle:
    case LightType::Mesh:
        return sampleAreaLight(light, P, u);
    case LightType::Environment:
        return sampleEnvironment(light, u);
    case LightType::Ambient:
        return {}; // no direction: not shadowed
    }
    return {};
}

} // namespace dhdr
