#include "bounce_light.h"

#include <algorithm>
#include <cmath>
#include <dhdr/deferred/sampling.h>
#include <glm/gtc/constants.hpp>

namespace dhdr {

BounceLighting::BounceLighting(const HitShading& hits) : m_hits(hits) {
    glm::vec3 lower, upper;
    m_empty = !hits.caster().bounds(lower, upper);
    if (m_empty) return;
    m_centre = 0.5 * (glm::dvec3(lower) + glm::dvec3(upper));
    m_radius = 0.5 * glm::length(glm::dvec3(upper) - glm::dvec3(lower)) * (1.0 + 0x1p-20);
}

glm::vec3 BounceLighting::irradiance(const SurfacePoint& at, const glm::vec3& N,
                                     std::uint64_t directions, std::int64_t hits, int samples,
                                     long long* rays) const {
    if (samples <= 0 || m_empty) return glm::vec3(0.0f);
    // The sphere grown by how far a ray's origin may lie off P (offsetRayOrigin: at most
    // √3 · √3 · error, and a float a coordinate).
    const glm::dvec3 toCentre = m_centre - glm::dvec3(at.P);
    const double reach =
        m_radius + 4.0 * double(at.error) +
        0x1p-20 * double(std::max({std::abs(at.P.x), std::abs(at.P.y), std::abs(at.P.z)}));
    const double outside = glm::dot(toCentre, toCentre) - reach * reach;
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    const RotatedHammersley sequence(directions);
    glm::dvec3 sum(0.0);
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 h = cosineHemisphere(sequence(std::uint32_t(i), std::uint32_t(samples)));
        const glm::vec3 wi = glm::normalize(h.x * t + h.y * b + h.z * N);
        // Below the triangle a shading normal leans over: no surface sends light that way.
        if (!(glm::dot(at.Ng, wi) > 0.0f)) continue;
        // A line from outside the sphere that misses it, or leaves it behind, hits nothing.
        const double along = glm::dot(toCentre, glm::normalize(glm::dvec3(wi)));
        if (outside > 0.0 && (along < 0.0 || along * along < outside)) continue;
        const Ray ray{glm::dvec3(offsetRayOrigin(at, wi)), glm::dvec3(wi)};
        sum += glm::dvec3(
            m_hits.trace(ray, SeedKey{hits, i, streamOf(SampleStream::BounceShadow)}, rays));
    }
    return glm::vec3(sum * (glm::pi<double>() / double(samples)));
}

} // namespace dhdr
