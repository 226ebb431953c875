#include <algorithm>
#include <cmath>
#include <dhdr/deferred/area_light.h>
#include <dhdr/deferred/light_eval.h>
#include <dhdr/deferred/light_sample.h>
#include <dhdr/deferred/sampling.h>

namespace dhdr {

namespace {

// A point sampled by area on a surface of area A with normal n (unit; sign ignored when
// two-sided): the solid-angle pdf is d² / (A |cos θ_l|) (pbrt-v4, Shape::PDF).
LightLiSample fromAreaPoint(const glm::vec3& P, const glm::vec3& point, const glm::vec3& n,
                            float area, bool twoSided, const glm::vec3& radiance) {
    LightLiSample s;
    const glm::vec3 d = point - P;
    const float dist2 = glm::dot(d, d);
    if (!(dist2 > 0.0f)) return s;
    s.distance = std::sqrt(dist2);
    s.wi = d / s.distance;
    float cosLight = -glm::dot(s.wi, n);
    if (twoSided) cosLight = std::abs(cosLight);
    if (!(cosLight > 0.0f)) return s;
    s.pdf = dist2 / (area * cosLight);
    s.L = radiance;
    return s;
}

} // namespace

LightLiSample sampleLi(const Light& light, const glm::vec3& P, glm::vec2 u) {
    LightLiSample s;
    if (light.type == LightType::Ambient) return s;
    if (light.type == LightType::Environment) {
        if (!light.ibl || light.ibl->sampler.empty()) return s;
        glm::vec3 radiance;
        const glm::vec3 d = light.ibl->sampler.sample(u, s.pdf, radiance);
        s.wi = fromEnvironment(light, d);
        s.L = radiance * light.color * light.intensity;
        s.distance = INFINITY;
        return s;
    }
    if (light.type == LightType::Directional && light.angle > 0.0f) {
        // A disk of the sky: directions uniform in its cone (pbrt-v4 SampleUniformCone), each
        // carrying the radiance E / Ω that spreads the light's illuminance over it.
        const float cosMax = std::cos(0.5f * light.angle);
        const float omega = 2.0f * kPi * (1.0f - cosMax);
        const glm::vec3 axis = -light.direction;
        glm::vec3 t, b;
        orthonormalBasis(axis, t, b);
        const glm::vec3 c = uniformCone(u, cosMax);
        s.wi = glm::normalize(c.x * t + c.y * b + c.z * axis);
        s.L = light.color * light.intensity / omega;
        s.pdf = 1.0f / omega;
        s.distance = INFINITY;
        return s;
    }
    if (!light.isArea()) {
        const IncidentLight in = incidentLight(light, P);
        s.L = in.illuminance;
        s.wi = in.L;
        s.distance =
            light.type == LightType::Directional ? INFINITY : glm::length(light.position - P);
        s.pdf = 1.0f;
        s.delta = true;
        return s;
    }
    const glm::vec3 toCentre = light.position - P;
    const float window = rangeWindow(glm::length(toCentre), light.range);
    if (light.type == LightType::Sphere) {
        const float d2 = glm::dot(toCentre, toCentre), r2 = light.radius * light.radius;
        if (!(d2 > r2)) return s; // inside the light: it is not blocked from anywhere
        const float d = std::sqrt(d2);
        const float cosMax = std::sqrt(std::max(0.0f, 1.0f - r2 / d2));
        glm::vec3 t, b;
        const glm::vec3 axis = toCentre / d;
        orthonormalBasis(axis, t, b);
        const glm::vec3 c = uniformCone(u, cosMax);
        s.wi = glm::normalize(t * c.x + b * c.y + axis * c.z);
        // The nearer intersection of the ray with the sphere (tangent rays touch it at
        // t = d cos θ).
        const float along = glm::dot(s.wi, toCentre);
        s.distance = along - std::sqrt(std::max(0.0f, r2 - (d2 - along * along)));
        s.pdf = 1.0f / (2.0f * kPi * (1.0f - cosMax));
        s.L = light.color * (light.intensity / (kPi * r2) * window);
        return s;
    }
    if (light.type == LightType::Rectangle) {
        const glm::vec3 right = glm::cross(light.up, light.direction);
        const glm::vec3 point = light.position + right * ((u.x - 0.5f) * light.width) +
                                light.up * ((u.y - 0.5f) * light.height);
        const float area = light.width * light.height;
        return fromAreaPoint(P, point, light.direction, area, false,
                             light.color * (light.intensity / area * window));
    }
    const EmitterMesh& m = *light.mesh;
    // The triangle whose share of the running area holds u.x, and u.x rescaled within it.
    const float target = u.x * m.area();
    const size_t t =
        std::min(size_t(std::upper_bound(m.cdf.begin(), m.cdf.end(), target) - m.cdf.begin()),
                 m.triangles() - 1);
    const float lo = t ? m.cdf[t - 1] : 0.0f;
    const float ux =
        std::clamp((target - lo) / std::max(m.cdf[t] - lo, 1e-30f), 0.0f, 0x1.fffffep-1f);
    const glm::vec2 b = uniformTriangle({ux, u.y});
    const glm::vec3 &a = m.vertices[3 * t], &p1 = m.vertices[3 * t + 1],
                    &p2 = m.vertices[3 * t + 2];
    const glm::vec3 point = a * b.x + p1 * b.y + p2 * (1.0f - b.x - b.y);
    const glm::vec3 n = glm::normalize(glm::cross(p1 - a, p2 - a));
    return fromAreaPoint(P, point, n, m.area(), true, light.color * (light.intensity * window));
}

} // namespace dhdr
