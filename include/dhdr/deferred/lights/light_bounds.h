// Where on screen a light can reach: the seed's per-light scissor rectangle.
#pragma once

#include <glm/glm.hpp>

namespace dhdr {

// Pixels [x0, x1) × [y0, y1); empty when x0 >= x1 or y0 >= y1.
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x0 >= x1 || y0 >= y1; }
};

// The pixels whose surface points may lie within a world-space sphere, for a camera given by
// its world-to-camera and camera-to-NDC (OpenGL) matrices: the projection of the sphere's
// camera-space bounding box, widened by a pixel. The whole image for a sphere that crosses the
// camera plane; empty for one wholly behind the camera.
PixelRect sphereScreenRect(const glm::dvec3& centre, double radius, const glm::dmat4& worldToCamera,
                           const glm::dmat4& cameraToNDC, int width, int height);

} // namespace dhdr
