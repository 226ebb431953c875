#include <cmath>
#include <dhdr/deferred/camera.h>
#include <glm/gtc/matrix_transform.hpp>

namespace dhdr {

Camera Camera::lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up,
                      double yfov) {
    Camera c;
    c.cameraToWorld = glm::inverse(glm::lookAt(eye, target, up));
    c.yfov = yfov;
    return c;
}

glm::dmat4 Camera::worldToCamera() const {
    return glm::inverse(cameraToWorld);
}

glm::dmat4 Camera::cameraToNDC(double aspect) const {
    return glm::perspective(yfov, aspect, znear, zfar);
}

Ray Camera::primaryRay(int x, int y, int width, int height) const {
    const double tanHalf = std::tan(0.5 * yfov);
    const double aspect = double(width) / double(height);
    const double sx = (2.0 * (x + 0.5) / width - 1.0) * tanHalf * aspect;
    const double sy = (1.0 - 2.0 * (y + 0.5) / height) * tanHalf;
    const glm::dvec3 dirCamera = glm::normalize(glm::dvec3(sx, sy, -1.0));
    return {position(), glm::normalize(glm::dvec3(cameraToWorld * glm::dvec4(dirCamera, 0.0)))};
}

} // namespace dhdr
