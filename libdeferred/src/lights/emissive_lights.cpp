#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/lights/emissive_lights.h>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr {

namespace {

// The mean colour of a texture: an emissive mesh is one light of one radiance.
glm::vec3 meanColour(const Texture& t) {
    glm::dvec3 sum(0.0);
    const size_t texels = size_t(t.width) * size_t(t.height);
    for (size_t i = 0; i < texels; ++i)
        sum += glm::dvec3(glm::vec3(t.texel(i)));
    return texels ? glm::vec3(sum / double(texels)) : glm::vec3(1.0f);
}

} // namespace

std::vector<Light> emissiveLights(const Scene& scene) {
    std::vector<Light> lights;
    for (const Mesh& mesh : scene.meshes) {
        const Material& m = scene.materials[size_t(mesh.material)];
        glm::vec3 radiance = m.emission;
        if (m.emissiveTexture.texture >= 0)
            radiance *= meanColour(scene.textures[size_t(m.emissiveTexture.texture)]);
        const float peak = std::max({radiance.r, radiance.g, radiance.b});
        if (!(peak > 0.0f) || mesh.triangles.empty()) continue;

        auto emitter = std::make_shared<EmitterMesh>();
        glm::dvec3 lo(INFINITY), hi(-INFINITY);
        double area = 0.0;
        for (const glm::uvec3& t : mesh.triangles) {
            const glm::vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]],
                            c = mesh.positions[t[2]];
            const double triangleArea =
                0.5 * glm::length(glm::cross(glm::dvec3(b - a), glm::dvec3(c - a)));
            if (!(triangleArea > 0.0)) continue; // degenerate: emits nothing
            emitter->vertices.insert(emitter->vertices.end(), {a, b, c});
            area += triangleArea;
            emitter->cdf.push_back(float(area));
            for (const glm::vec3& v : {a, b, c}) {
                lo = glm::min(lo, glm::dvec3(v));
                hi = glm::max(hi, glm::dvec3(v));
            }
        }
        if (emitter->cdf.empty()) continue;

        Light light;
        light.type = LightType::Mesh;
        light.name =
            scene.objectNames.empty() ? "emissive mesh" : scene.objectNames[size_t(mesh.object)];
        light.color = radiance;
        light.intensity = 1.0f;
        const glm::dvec3 centre = 0.5 * (lo + hi);
        light.position = glm::vec3(centre);
        light.radius = float(0.5 * glm::length(hi - lo));
        light.range = light.radius + std::sqrt(float(area) / (kPi * kEmitterCutoff));
        light.mesh = std::move(emitter);
        lights.push_back(std::move(light));
    }
    return lights;
}

std::vector<Light> sceneLightList(const Scene& scene, bool ownLights, bool emissive,
                                  bool radiometric, size_t* emitters) {
    std::vector<Light> lights = ownLights ? scene.lights : std::vector<Light>{};
    const std::vector<Light> glowing = emissive ? emissiveLights(scene) : std::vector<Light>{};
    lights.insert(lights.end(), glowing.begin(), glowing.end());
    if (emitters) *emitters = glowing.size();
    if (radiometric) toRadiometricUnits(lights);
    return lights;
}

} // namespace dhdr
