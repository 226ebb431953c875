#include <cmath>
#include <dhdr/deferred/camera.h>
#include <glm/gtc/matrix_transform.hpp>

namespace dhdr {

Camera Camera::lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up,
                      double yfov) {
    Camera c;
    const glm::dvec3 forward = glm::normalize(target - eye);
    glm::dvec3 u = up;
    if (glm::length(glm::cross(forward, glm::normalize(up))) < 1e-9)
        u = forward.y < 0.0 ? glm::dvec3(0.0, 0.0, -1.0) : glm::dvec3(0.0, 0.0, 1.0);
    if (glm::length(glm::cross(forward, u)) < 1e-9) u = glm::dvec3(0.0, 1.0, 0.0);
    c.cameraToWorld = glm::inverse(glm::lookAt(eye, target, u));
    c.yfov = yfov;
    return c;
}

glm::dmat4 Camera::worldToCamera() const {
    return glm::inverse(cameraToWorld);
}

glm::dmat4 Camera::cameraToNDC(double aspect) const {
    if (orthographic) return glm::ortho(-ymag * aspect, ymag * aspect, -ymag, ymag, znear, zfar);
    return glm::perspective(yfov, aspect, znear, zfar);
}

Ray Camera::primaryRay(int x, int y, int width, int height) const {
    const double aspect = double(width) / double(height);
    const double half = orthographic ? ymag : std::tan(0.5 * yfov);
    const double sx = (2.0 * (x + 0.5) / width - 1.0) * half * aspect;
    const double sy = (1.0 - 2.0 * (y + 0.5) / height) * half;
    if (orthographic)
        return {glm::dvec3(cameraToWorld * glm::dvec4(sx, sy, 0.0, 1.0)),
                glm::normalize(glm::dvec3(cameraToWorld * glm::dvec4(0.0, 0.0, -1.0, 0.0)))};
    const glm::dvec3 dirCamera = glm::normalize(glm::dvec3(sx, sy, -1.0));
    return {position(), glm::normalize(glm::dvec3(cameraToWorld * glm::dvec4(dirCamera, 0.0)))};
}

} // namespace dhdr
