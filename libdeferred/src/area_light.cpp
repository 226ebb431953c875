#include <cmath>
#include <dhdr/deferred/area_light.h>
#include <dhdr/deferred/light_eval.h>

namespace dhdr {

float sphereIrradiance(const glm::vec3& N, const glm::vec3& toCentre, float radius) {
    const float d2 = glm::dot(toCentre, toCentre);
    const float sinSigma2 = std::min(radius * radius / d2, 1.0f);
    const float cosTheta = glm::dot(N, toCentre) / std::sqrt(d2);
    const float sinSigma = std::sqrt(sinSigma2);
    if (cosTheta >= sinSigma) return kPi * sinSigma2 * cosTheta; // wholly above the horizon
    if (cosTheta <= -sinSigma) return 0.0f;                      // wholly below
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    const float x = std::sqrt(std::max(1.0f / sinSigma2 - 1.0f, 0.0f)); // cot σ
    const float y = std::clamp(-x * cosTheta / std::max(sinTheta, 1e-7f), -1.0f, 1.0f);
    const float s = sinTheta * std::sqrt(1.0f - y * y);
    return (cosTheta * std::acos(y) - x * s) * sinSigma2 + std::atan2(s, x);
}

float polygonIrradiance(const glm::vec3& N, const glm::vec3* vertices, int count) {
    // Clip against the plane N · v = 0 (Sutherland-Hodgman); a convex quad gains at most
    // one vertex.
    glm::vec3 clipped[8];
    int n = 0;
    for (int i = 0; i < count; ++i) {
        const glm::vec3& a = vertices[i];
        const glm::vec3& b = vertices[(i + 1) % count];
        const float da = glm::dot(N, a), db = glm::dot(N, b);
        if (da >= 0.0f) clipped[n++] = a;
        if ((da >= 0.0f) != (db >= 0.0f)) clipped[n++] = a + (b - a) * (da / (da - db));
    }
    if (n < 3) return 0.0f;
    float sum = 0.0f;
    for (int i = 0; i < n; ++i) {
        const glm::vec3 a = glm::normalize(clipped[i]);
        const glm::vec3 b = glm::normalize(clipped[(i + 1) % n]);
        const glm::vec3 c = glm::cross(a, b);
        const float len = glm::length(c);
        if (len < 1e-12f) continue;
        const float theta = std::atan2(len, glm::dot(a, b));
        sum += theta * glm::dot(N, c) / len;
    }
    return 0.5f * std::abs(sum);
}

void rectangleCorners(const Light& light, glm::vec3 corners[4]) {
    const glm::vec3 right = glm::cross(light.up, light.direction);
    const glm::vec3 u = right * (0.5f * light.width), v = light.up * (0.5f * light.height);
    corners[0] = light.position - u - v;
    corners[1] = light.position + u - v;
    corners[2] = light.position + u + v;
    corners[3] = light.position - u + v;
}

glm::vec3 shadeAreaLight(const Light& light, const PbrSurface& s, const glm::vec3& P,
                         const glm::vec3& N, const glm::vec3& V) {
    const glm::vec3 toCentre = light.position - P;
    const float d2 = glm::dot(toCentre, toCentre);
    const float d = std::sqrt(d2);
    const float window = rangeWindow(d, light.range);
    if (window == 0.0f || d == 0.0f) return glm::vec3(0.0f);
    const glm::vec3 Lc = toCentre / d;

    float irradiance = 0.0f; // per unit radiance
    float radiance = 0.0f;
    float intensity = light.intensity; // towards P, candela
    float size = 0.0f;                 // radius of the light, or of a disk of equal area
    glm::vec3 closest(0.0f);
    const glm::vec3 R = glm::reflect(-V, N);
    if (light.type == LightType::Sphere) {
        irradiance = sphereIrradiance(N, toCentre, light.radius);
        radiance = light.intensity / (kPi * light.radius * light.radius);
        size = light.radius;
        // The point of the sphere nearest the reflected ray.
        const glm::vec3 centreToRay = glm::dot(toCentre, R) * R - toCentre;
        const float len = glm::length(centreToRay);
        closest = toCentre + centreToRay * (len > 0.0f ? std::min(1.0f, light.radius / len) : 0.0f);
    } else {
        // One-sided: nothing reaches a point behind the emitting face.
        const float facing = -glm::dot(Lc, light.direction);
        if (facing <= 0.0f) return glm::vec3(0.0f);
        glm::vec3 corners[4];
        rectangleCorners(light, corners);
        for (glm::vec3& c : corners)
            c -= P;
        irradiance = polygonIrradiance(N, corners, 4);
        const float area = light.width * light.height;
        radiance = light.intensity / area;
        intensity = light.intensity * facing;
        size = std::sqrt(area / kPi);
        // Where the reflected ray meets the light's plane, clamped to the rectangle.
        const float denom = glm::dot(R, light.direction);
        glm::vec3 hit = toCentre;
        if (denom < -1e-6f) hit = R * (glm::dot(toCentre, light.direction) / denom);
        const glm::vec3 right = glm::cross(light.up, light.direction);
        const glm::vec3 local = hit - toCentre;
        const float u = std::clamp(glm::dot(local, right), -0.5f * light.width, 0.5f * light.width);
        const float v =
            std::clamp(glm::dot(local, light.up), -0.5f * light.height, 0.5f * light.height);
        closest = toCentre + u * right + v * light.up;
    }

    glm::vec3 Lo(0.0f);
    const float NdotV = glm::dot(N, V);
    // Diffuse: (1 − F) c_diff / π × E, with F at the centre's half vector.
    if (irradiance > 0.0f && NdotV > 0.0f) {
        const glm::vec3 F =
            schlickFresnel(s.F0(), std::max(glm::dot(V, glm::normalize(Lc + V)), 0.0f));
        Lo += (glm::vec3(1.0f) - F) * s.diffuseColor() * (radiance * irradiance / kPi);
    }
    // Specular: the lobe at the representative direction, energy-normalized.
    const glm::vec3 Ls = glm::normalize(closest);
    const float NdotL = glm::dot(N, Ls);
    if (NdotL > 0.0f && NdotV > 0.0f) {
        const glm::vec3 H = glm::normalize(Ls + V);
        const float alpha = s.alpha();
        const float widened = std::min(1.0f, alpha + size / (2.0f * d));
        const float normalization = (alpha / widened) * (alpha / widened);
        const glm::vec3 F = schlickFresnel(s.F0(), std::max(glm::dot(V, H), 0.0f));
        const float spec = ggxDistribution(std::max(glm::dot(N, H), 0.0f), alpha) *
                           smithGgxCorrelatedVisibility(NdotL, NdotV, alpha) * normalization;
        Lo += F * (spec * intensity / d2 * NdotL);
    }
    return Lo * light.color * window;
}

} // namespace dhdr
