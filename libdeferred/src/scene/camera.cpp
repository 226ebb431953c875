#include <cmath>
#include <cstdio>
#include <dhdr/deferred/scene/camera.h>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <string>

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

namespace {

// Finite, and held by a float (the G-buffer's header stores the camera's matrices as floats).
bool fitsFloat(double v) {
    return std::isfinite(v) && std::abs(v) <= double(std::numeric_limits<float>::max());
}

bool fitsFloat(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!fitsFloat(m[c][r])) return false;
    return true;
}

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

} // namespace

std::string Camera::problem() const {
    if (!fitsFloat(cameraToWorld))
        return "its camera-to-world matrix is not finite (or holds a number no float holds)";
    // The matrix is invertible when its three axes span space: each of non-zero length and the
    // volume they span not negligible against the product of their lengths.
    const glm::dvec3 x(cameraToWorld[0]), y(cameraToWorld[1]), z(cameraToWorld[2]);
    const double lengths = glm::length(x) * glm::length(y) * glm::length(z);
    const double volume = std::abs(glm::dot(x, glm::cross(y, z)));
    if (!(lengths > 0.0) || !(volume > 1e-12 * lengths) || !fitsFloat(worldToCamera()))
        return "its camera-to-world matrix is not invertible (a node scaled by 0, or axes that "
               "coincide)";
    if (orthographic) {
        if (!fitsFloat(ymag) || !(ymag > 0.0))
            return "its ymag, " + number(ymag) + ", is not a positive number";
        if (!fitsFloat(znear) || !(znear >= 0.0))
            return "its znear, " + number(znear) + ", is not a number >= 0";
    } else {
        const double pi = 3.14159265358979323846;
        if (!std::isfinite(yfov) || !(yfov > 0.0) || !(yfov < pi))
            return "its vertical field of view, " + number(yfov * 180.0 / pi) +
                   " degrees, is not between 0 and 180";
        if (!fitsFloat(znear) || !(znear > 0.0))
            return "its znear, " + number(znear) + ", is not a positive number";
    }
    if (!fitsFloat(zfar) || !(zfar > znear))
        return "its zfar, " + number(zfar) + ", is not a finite number greater than znear (" +
               number(znear) + ")";
    return {};
}

Ray Camera::primaryRay(int x, int y, int width, int height) const {
    return rayThrough(x + 0.5, y + 0.5, width, height);
}

Ray Camera::rayThrough(double px, double py, int width, int height) const {
    const double aspect = double(width) / double(height);
    const double half = orthographic ? ymag : std::tan(0.5 * yfov);
    const double sx = (2.0 * px / width - 1.0) * half * aspect;
    const double sy = (1.0 - 2.0 * py / height) * half;
    if (orthographic)
        return {glm::dvec3(cameraToWorld * glm::dvec4(sx, sy, 0.0, 1.0)),
                glm::normalize(glm::dvec3(cameraToWorld * glm::dvec4(0.0, 0.0, -1.0, 0.0)))};
    const glm::dvec3 dirCamera = glm::normalize(glm::dvec3(sx, sy, -1.0));
    return {position(), glm::normalize(glm::dvec3(cameraToWorld * glm::dvec4(dirCamera, 0.0)))};
}

} // namespace dhdr
