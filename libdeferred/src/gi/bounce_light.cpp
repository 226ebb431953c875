#include "gi/bounce_light.h"

#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/scene/scene.h>
#include <glm/gtc/constants.hpp>

namespace dhdr {

namespace {

// More meshes than this: one sphere round the scene (testing each would cost more than the
// rays it saves).
constexpr size_t kMaxSpheres = 32;

} // namespace

BounceLighting::BounceLighting(const HitShading& hits) : m_hits(hits) {
    glm::vec3 lower, upper;
    m_empty = !hits.caster().bounds(lower, upper);
    if (m_empty) return;
    const std::vector<Mesh>& meshes = hits.caster().scene().meshes;
    bool usable = meshes.size() <= kMaxSpheres;
    for (size_t i = 0; usable && i < meshes.size(); ++i) {
        const Mesh& mesh = meshes[i];
        if (mesh.triangles.empty() || mesh.positions.empty()) continue;
        glm::dvec3 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec3& p : mesh.positions) {
            lo = glm::min(lo, glm::dvec3(p));
            hi = glm::max(hi, glm::dvec3(p));
        }
        const glm::dvec3 centre = 0.5 * (lo + hi);
        double r2 = 0.0, size = 0.0;
        for (const glm::vec3& p : mesh.positions) {
            const glm::dvec3 d = glm::dvec3(p) - centre;
            r2 = std::max(r2, glm::dot(d, d));
            size = std::max(
                {size, std::abs(double(p.x)), std::abs(double(p.y)), std::abs(double(p.z))});
        }
        // Widened, as the caster's bounds are, by far more than any kernel's rounding of a hit.
        const double radius = std::sqrt(r2) * (1.0 + 0x1p-20) + size * 0x1p-12;
        usable = std::isfinite(radius) && std::isfinite(size);
        m_spheres.push_back({centre, radius});
    }
    if (usable && !m_spheres.empty()) return;
    m_spheres.assign(
        1, Sphere{0.5 * (glm::dvec3(lower) + glm::dvec3(upper)),
                  0.5 * glm::length(glm::dvec3(upper) - glm::dvec3(lower)) * (1.0 + 0x1p-20)});
}

glm::vec3 BounceLighting::irradiance(const SurfacePoint& at, const glm::vec3& N,
                                     std::uint64_t directions, std::int64_t hits, int samples,
                                     long long* rays) const {
    if (samples <= 0 || m_empty) return glm::vec3(0.0f);
    // The spheres grown by how far a ray's origin may lie off P (offsetRayOrigin: at most
    // √3 · √3 · error, and a float a coordinate).
    const double slack =
        4.0 * double(at.error) +
        0x1p-20 * double(std::max({std::abs(at.P.x), std::abs(at.P.y), std::abs(at.P.z)}));
    // A direction d meets sphere k only if d · c_k ≥ √(|c_k|² − reach_k²), c_k the centre
    // from P. That test in float, against a bound lowered by far more than its rounding
    // (|d| = 1 ± 2⁻²², c_k and the products a few ulps): a direction it keeps may still miss
    // (a miss adds nothing), one it drops misses.
    glm::vec3 toCentre[kMaxSpheres];
    float least[kMaxSpheres];
    const size_t spheres = m_spheres.size();
    bool inside = false;
    for (size_t k = 0; k < spheres; ++k) {
        const glm::dvec3 c = m_spheres[k].centre - glm::dvec3(at.P);
        const double reach = m_spheres[k].radius + slack;
        const double outside = glm::dot(c, c) - reach * reach;
        inside = inside || !(outside > 0.0);
        toCentre[k] = glm::vec3(c);
        least[k] = float(std::sqrt(std::max(outside, 0.0)) - 0x1p-16 * glm::length(c));
    }
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    const RotatedHammersley sequence(directions);
    glm::dvec3 sum(0.0);
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 h = cosineHemisphere(sequence(std::uint32_t(i), std::uint32_t(samples)));
        const glm::vec3 wi = glm::normalize(h.x * t + h.y * b + h.z * N);
        // Below the triangle a shading normal leans over: no surface sends light that way.
        if (!(glm::dot(at.Ng, wi) > 0.0f)) continue;
        // A line from outside every sphere that misses each, or leaves it behind, hits nothing.
        if (!inside) {
            bool towards = false;
            for (size_t k = 0; k < spheres && !towards; ++k)
                towards = !(glm::dot(toCentre[k], wi) < least[k]);
            if (!towards) continue;
        }
        const Ray ray{glm::dvec3(offsetRayOrigin(at, wi)), glm::dvec3(wi)};
        sum += glm::dvec3(
            m_hits.trace(ray, SeedKey{hits, i, streamOf(SampleStream::BounceShadow)}, rays));
    }
    return glm::vec3(sum * (glm::pi<double>() / double(samples)));
}

} // namespace dhdr
