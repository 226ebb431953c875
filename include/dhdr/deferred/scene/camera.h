// A pinhole or orthographic camera in the glTF / OpenGL convention: it looks down its local
// −Z, +Y is up.
#pragma once

#include <glm/glm.hpp>
#include <string>

namespace dhdr {

struct Ray {
    glm::dvec3 origin;
    glm::dvec3 direction; // unit length
};

struct Camera {
    glm::dmat4 cameraToWorld{1.0};
    // Full vertical field of view, radians (perspective).
    double yfov = 0.6911112; // 39.6°, Blender's default 50 mm lens
    // Orthographic: parallel rays along −Z from an image plane of half-height `ymag` scene
    // units (glTF's camera.orthographic.ymag); the half-width follows the image's aspect.
    bool orthographic = false;
    double ymag = 1.0;
    double znear = 0.01;
    double zfar = 1000.0;

    // A camera at `eye` looking at `target` (which must differ). When `up` is parallel to the
    // view direction (a camera looking straight down with up +Y), the image's up is the
    // scene's −Z looking down, +Z looking up.
    static Camera lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up,
                         double yfov);

    glm::dvec3 position() const { return glm::dvec3(cameraToWorld[3]); }
    glm::dmat4 worldToCamera() const;
    // OpenGL projection (NDC in [−1, 1]³) for an image of the given aspect (width / height):
    // perspective, or glm::ortho for an orthographic camera.
    glm::dmat4 cameraToNDC(double aspect) const;
    glm::dmat4 worldToNDC(double aspect) const { return cameraToNDC(aspect) * worldToCamera(); }

    // Why the camera cannot be rendered from, empty when it can: a camera-to-world matrix that
    // is not finite, does not fit a float (the G-buffer stores it as one) or is not invertible
    // (a node scaled by 0); a vertical field of view outside (0°, 180°); ymag not a positive
    // float; znear not > 0 (perspective) or ≥ 0 (orthographic); zfar not finite or not > znear.
    std::string problem() const;

    // The primary ray through the centre of pixel (x, y) of a width × height image, y down.
    Ray primaryRay(int x, int y, int width, int height) const;
    // The ray through image position (px, py) of a width × height image, in pixels from its
    // top-left corner (pixel (x, y)'s centre is (x + 0.5, y + 0.5)).
    Ray rayThrough(double px, double py, int width, int height) const;
};

} // namespace dhdr
