#include <algorithm>
#include <cmath>
#include <dhdr/deferred/lights/light_bounds.h>

namespace dhdr {

PixelRect sphereScreenRect(const glm::dvec3& centre, double radius, const glm::dmat4& worldToCamera,
                           const glm::dmat4& cameraToNDC, int width, int height) {
    const PixelRect whole{0, 0, width, height};
    if (!std::isfinite(radius)) return whole;
    const double r = radius;
    const glm::dvec3 c = glm::dvec3(worldToCamera * glm::dvec4(centre, 1.0));
    // The camera looks down −z: a sphere wholly at z > 0 is behind it, one reaching z > −ε
    // crosses the plane where projection breaks down.
    if (c.z - r > 0.0) return {};
    if (c.z + r > -1e-6) return whole;

    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    for (int i = 0; i < 8; ++i) {
        const glm::dvec3 corner =
            c + r * glm::dvec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
        const glm::dvec4 clip = cameraToNDC * glm::dvec4(corner, 1.0);
        // Pixel coordinates of the corner (y down).
        const double px = (clip.x / clip.w + 1.0) * 0.5 * width;
        const double py = (1.0 - clip.y / clip.w) * 0.5 * height;
        xmin = std::min(xmin, px);
        xmax = std::max(xmax, px);
        ymin = std::min(ymin, py);
        ymax = std::max(ymax, py);
    }
    // A pixel is shaded at its centre; one pixel of margin absorbs the header's float matrices.
    auto clampX = [&](double v) { return int(std::clamp(v, 0.0, double(width))); };
    auto clampY = [&](double v) { return int(std::clamp(v, 0.0, double(height))); };
    return {clampX(std::floor(xmin) - 1), clampY(std::floor(ymin) - 1), clampX(std::ceil(xmax) + 1),
            clampY(std::ceil(ymax) + 1)};
}

} // namespace dhdr
