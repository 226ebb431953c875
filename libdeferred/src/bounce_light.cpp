#include "bounce_light.h"

#include <dhdr/deferred/sampling.h>
#include <glm/gtc/constants.hpp>

namespace dhdr {

glm::vec3 BounceLighting::irradiance(const SurfacePoint& at, const glm::vec3& N,
                                     std::uint64_t directions, std::int64_t hits, int samples,
                                     long long* rays) const {
    if (samples <= 0) return glm::vec3(0.0f);
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    const RotatedHammersley sequence(directions);
    glm::dvec3 sum(0.0);
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 h = cosineHemisphere(sequence(std::uint32_t(i), std::uint32_t(samples)));
        const glm::vec3 wi = glm::normalize(h.x * t + h.y * b + h.z * N);
        // Below the triangle a shading normal leans over: no surface sends light that way.
        if (!(glm::dot(at.Ng, wi) > 0.0f)) continue;
        const Ray ray{glm::dvec3(offsetRayOrigin(at, wi)), glm::dvec3(wi)};
        sum += glm::dvec3(
            m_hits.trace(ray, SeedKey{hits, i, streamOf(SampleStream::BounceShadow)}, rays));
    }
    return glm::vec3(sum * (glm::pi<double>() / double(samples)));
}

} // namespace dhdr
