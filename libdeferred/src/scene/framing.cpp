#include <algorithm>
#include <cmath>
#include <dhdr/deferred/scene/scene.h>
#include <glm/gtc/matrix_transform.hpp>

namespace dhdr {

Camera frameScene(const Scene& scene, const Camera& like, double aspect) {
    return frameBounds(scene.boundsMin(), scene.boundsMax(), like, aspect);
}

Camera frameBounds(const glm::dvec3& lo, const glm::dvec3& hi, const Camera& like, double aspect) {
    const glm::dvec3 centre = 0.5 * (lo + hi);
    // The bounding sphere of the box: it stays in view from every direction.
    const double radius = std::max(0.5 * glm::length(hi - lo), 1e-6);
    Camera c = like;
    const glm::dvec3 forward =
        glm::normalize(glm::dvec3(like.cameraToWorld * glm::dvec4(0.0, 0.0, -1.0, 0.0)));
    const glm::dvec3 up =
        glm::normalize(glm::dvec3(like.cameraToWorld * glm::dvec4(0.0, 1.0, 0.0, 0.0)));
    double distance = 0.0;
    if (like.orthographic) {
        // The sphere's diameter fits the shorter side of the image plane.
        c.ymag = aspect >= 1.0 ? radius : radius / aspect;
        distance = 2.0 * radius;
    } else {
        // The half-angle of the narrower side of the view; the sphere touches its edges.
        const double halfY = 0.5 * like.yfov;
        const double halfX = std::atan(std::tan(halfY) * aspect);
        distance = radius / std::sin(std::min(halfX, halfY));
    }
    const glm::dvec3 eye = centre - forward * distance;
    c.cameraToWorld = glm::inverse(glm::lookAt(eye, centre, up));
    c.znear = std::max(distance - 1.01 * radius, 1e-3 * distance);
    c.zfar = distance + 1.01 * radius;
    return c;
}

} // namespace dhdr
