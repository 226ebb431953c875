#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/lights/area.h>
#include <dhdr/deferred/lights/punctual.h>

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

namespace {

// The point of triangle abc nearest p (Ericson 2005, "Real-Time Collision Detection", 5.1.5).
glm::vec3 closestPointOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                                 const glm::vec3& c) {
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) return a;
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) return b;
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + ab * (d1 / (d1 - d3));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) return c;
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + ac * (d2 / (d2 - d6));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const float denom = 1.0f / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// How far a point must stand off an emitter's plane to be lit by it: the error of the signed
// distance computed in float from coordinates of magnitude `scale` (a subtraction and a dot
// product, plus the point's own rounding), 8 ulps. A point in the plane sees the emitter edge
// on, and gets nothing from it; rounding must not decide otherwise (the emitter's own pixels
// would be lit by the whole of it).
float planeTolerance(const glm::vec3& P, const glm::vec3& onPlane) {
    const glm::vec3 a = glm::abs(P) + glm::abs(onPlane);
    return 8.0f * 0x1p-24f * std::max({a.x, a.y, a.z});
}

// What the diffuse and specular lobes need of an area light seen from a point.
struct AreaView {
    float irradiance = 0.0f; // per unit radiance
    float radiance = 0.0f;
    float intensity = 0.0f;  // towards the point, candela
    float size = 0.0f;       // radius of the light, or of a disk of equal area
    glm::vec3 closest{0.0f}; // representative point for the specular lobe, relative to P
};

bool viewSphere(const Light& light, const glm::vec3& toCentre, const glm::vec3& N,
                const glm::vec3& R, AreaView& v) {
    v.irradiance = sphereIrradiance(N, toCentre, light.radius);
    v.radiance = light.intensity / (kPi * light.radius * light.radius);
    v.intensity = light.intensity;
    v.size = light.radius;
    // The point of the sphere nearest the reflected ray.
    const glm::vec3 centreToRay = glm::dot(toCentre, R) * R - toCentre;
    const float len = glm::length(centreToRay);
    v.closest = toCentre + centreToRay * (len > 0.0f ? std::min(1.0f, light.radius / len) : 0.0f);
    return true;
}

bool viewRectangle(const Light& light, const glm::vec3& P, const glm::vec3& toCentre,
                   const glm::vec3& Lc, const glm::vec3& N, const glm::vec3& R, AreaView& v) {
    // One-sided: nothing reaches a point behind the emitting face, nor one in its plane.
    if (!(glm::dot(-toCentre, light.direction) > planeTolerance(P, light.position))) return false;
    const float facing = -glm::dot(Lc, light.direction);
    glm::vec3 corners[4];
    rectangleCorners(light, corners);
    for (glm::vec3& c : corners)
        c -= P;
    v.irradiance = polygonIrradiance(N, corners, 4);
    const float area = light.width * light.height;
    v.radiance = light.intensity / area;
    v.intensity = light.intensity * facing;
    v.size = std::sqrt(area / kPi);
    // Where the reflected ray meets the light's plane, clamped to the rectangle.
    const float denom = glm::dot(R, light.direction);
    glm::vec3 hit = toCentre;
    if (denom < -1e-6f) hit = R * (glm::dot(toCentre, light.direction) / denom);
    const glm::vec3 right = glm::cross(light.up, light.direction);
    const glm::vec3 local = hit - toCentre;
    const float u = std::clamp(glm::dot(local, right), -0.5f * light.width, 0.5f * light.width);
    const float w =
        std::clamp(glm::dot(local, light.up), -0.5f * light.height, 0.5f * light.height);
    v.closest = toCentre + u * right + w * light.up;
    return true;
}

// An emissive mesh: the exact irradiance summed over its triangles (each a polygon of
// Lambert's formula); for the specular lobe, of the points of each triangle nearest where the
// reflected ray meets its plane, the one nearest its hit (for a flat mesh, the point of the
// mesh nearest the hit, as for a rectangle).
bool viewMesh(const Light& light, const glm::vec3& P, const glm::vec3& Lc, const glm::vec3& N,
              const glm::vec3& R, AreaView& v) {
    const EmitterMesh& m = *light.mesh;
    float best = INFINITY, projected = 0.0f;
    for (size_t t = 0; t < m.triangles(); ++t) {
        glm::vec3 tri[3] = {m.vertices[3 * t] - P, m.vertices[3 * t + 1] - P,
                            m.vertices[3 * t + 2] - P};
        const glm::vec3 n = glm::cross(tri[1] - tri[0], tri[2] - tri[0]); // 2 · area · normal
        const float nl = glm::length(n);
        // A triangle whose plane holds P is seen edge on (its own pixels among them).
        if (!(nl > 0.0f) ||
            !(std::abs(glm::dot(n, tri[0])) > nl * planeTolerance(P, m.vertices[3 * t])))
            continue;
        v.irradiance += polygonIrradiance(N, tri, 3);
        // Projected towards the light's centre, as a rectangle light's intensity is.
        projected += 0.5f * std::abs(glm::dot(n, Lc));
        const float towards = glm::dot(n, tri[0]);
        const float denom = glm::dot(R, n);
        glm::vec3 hit = (tri[0] + tri[1] + tri[2]) / 3.0f;
        if (std::abs(denom) > 1e-12f && towards / denom > 0.0f) hit = R * (towards / denom);
        const glm::vec3 q = closestPointOnTriangle(hit, tri[0], tri[1], tri[2]);
        if (const float gap = glm::length(q - hit); gap < best) {
            best = gap;
            v.closest = q;
        }
    }
    v.radiance = light.intensity;
    // Intensity towards the point: radiance × the mesh's area projected across the view.
    v.intensity = light.intensity * projected;
    v.size = std::sqrt(m.area() / kPi);
    return v.irradiance > 0.0f || projected > 0.0f;
}

} // namespace

float areaLightIrradiance(const Light& light, const glm::vec3& P, const glm::vec3& N) {
    const glm::vec3 toCentre = light.position - P;
    if (light.type == LightType::Sphere)
        return glm::dot(toCentre, toCentre) > light.radius * light.radius
                   ? sphereIrradiance(N, toCentre, light.radius)
                   : 0.0f;
    if (light.type == LightType::Rectangle) {
        if (!(glm::dot(-toCentre, light.direction) > planeTolerance(P, light.position)))
            return 0.0f;
        glm::vec3 corners[4];
        rectangleCorners(light, corners);
        for (glm::vec3& c : corners)
            c -= P;
        return polygonIrradiance(N, corners, 4);
    }
    if (light.type != LightType::Mesh || !light.mesh) return 0.0f;
    // Both faces of every triangle, as sampleAreaLight draws them; edge-on ones subtend nothing.
    const EmitterMesh& m = *light.mesh;
    float sum = 0.0f;
    for (size_t t = 0; t < m.triangles(); ++t) {
        glm::vec3 tri[3] = {m.vertices[3 * t] - P, m.vertices[3 * t + 1] - P,
                            m.vertices[3 * t + 2] - P};
        const glm::vec3 n = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
        const float nl = glm::length(n);
        if (!(nl > 0.0f) ||
            !(std::abs(glm::dot(n, tri[0])) > nl * planeTolerance(P, m.vertices[3 * t])))
            continue;
        sum += polygonIrradiance(N, tri, 3);
    }
    return sum;
}

glm::vec3 shadeAreaLight(const Light& light, const PbrSurface& s, const glm::vec3& P,
                         const glm::vec3& N, const glm::vec3& V) {
    const glm::vec3 toCentre = light.position - P;
    const float d2 = glm::dot(toCentre, toCentre);
    const float d = std::sqrt(d2);
    const float window = rangeWindow(d, light.range);
    if (window == 0.0f || d == 0.0f) return glm::vec3(0.0f);
    const glm::vec3 Lc = toCentre / d;
    const glm::vec3 R = glm::reflect(-V, N);
    AreaView view;
    const bool seen = light.type == LightType::Sphere ? viewSphere(light, toCentre, N, R, view)
                      : light.type == LightType::Rectangle
                          ? viewRectangle(light, P, toCentre, Lc, N, R, view)
                          : viewMesh(light, P, Lc, N, R, view);
    if (!seen) return glm::vec3(0.0f);

    glm::vec3 Lo(0.0f);
    const float NdotV = glm::dot(N, V);
    // Diffuse: the diffuse layer towards the centre × E, with F at the centre's half vector.
    if (view.irradiance > 0.0f && NdotV > 0.0f) {
        const glm::vec3 F = s.fresnel(std::max(glm::dot(V, glm::normalize(Lc + V)), 0.0f));
        Lo += diffuseBrdf(s, N, V, Lc, F) * (view.radiance * view.irradiance);
        // The multiple-scattering lobe is nearly diffuse: the irradiance, at the centre's
        // angle.
        Lo += multipleScatteringBrdf(s, NdotV, std::max(glm::dot(N, Lc), 0.0f)) *
              (view.radiance * view.irradiance);
    }
    // Specular: the lobe at the representative direction, energy-normalized.
    const glm::vec3 Ls = glm::normalize(view.closest);
    const float NdotL = glm::dot(N, Ls);
    if (NdotL > 0.0f && NdotV > 0.0f) {
        const glm::vec3 H = glm::normalize(Ls + V);
        const float alpha = s.alpha();
        const float widened = std::min(1.0f, alpha + view.size / (2.0f * d));
        const float normalization = (alpha / widened) * (alpha / widened);
        const glm::vec3 F = s.fresnel(std::max(glm::dot(V, H), 0.0f));
        const float spec = ggxDistribution(std::max(glm::dot(N, H), 0.0f), alpha) *
                           smithGgxCorrelatedVisibility(NdotL, NdotV, alpha) * normalization;
        Lo += F * (spec * view.intensity / d2 * NdotL);
    }
    return Lo * light.color * window;
}

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

LightLiSample sampleAreaLight(const Light& light, const glm::vec3& P, glm::vec2 u) {
    LightLiSample s;
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
    if (light.type != LightType::Mesh || !light.mesh || light.mesh->triangles() == 0) return s;
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
