#include "render/pixel_samples.h"

#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>

namespace dhdr {

bool probesDiffer(const ProbeHit& a, const ProbeHit& b) {
    if (a.hit != b.hit) return true;
    if (!a.hit) return false;
    if (a.object != b.object || a.material != b.material) return true;
    if (glm::dot(a.normal, b.normal) < 0.906) return true; // cos 25°
    const glm::dvec3 step = b.position - a.position;
    const double length = glm::length(step);
    if (!(length > 0.0)) return false;
    return std::abs(glm::dot(step, a.normal)) > 0.25 * length ||
           std::abs(glm::dot(step, b.normal)) > 0.25 * length;
}

std::vector<std::uint8_t> pixelsToRefine(OIIO::ROI rows, int width, int height,
                                         const std::function<ProbeHit(double, double)>& probe,
                                         int nthreads) {
    // Centres of the rows and the rows above and below; corners of the rows' pixels.
    const int c0 = std::max(0, rows.ybegin - 1), c1 = std::min(height, rows.yend + 1);
    const size_t w = size_t(width);
    std::vector<ProbeHit> centres(size_t(c1 - c0) * w);
    std::vector<ProbeHit> corners(size_t(rows.height() + 1) * (w + 1));
    parallelRows(c0, c1, nthreads, [&](int64_t y) {
        for (int x = 0; x < width; ++x)
            centres[size_t(y - c0) * w + size_t(x)] = probe(x + 0.5, double(y) + 0.5);
    });
    parallelRows(rows.ybegin, rows.yend + 1, nthreads, [&](int64_t y) {
        for (int x = 0; x <= width; ++x)
            corners[size_t(y - rows.ybegin) * (w + 1) + size_t(x)] = probe(x, double(y));
    });
    std::vector<std::uint8_t> refine(size_t(rows.height()) * w, 0);
    parallelRows(rows.ybegin, rows.yend, nthreads, [&](int64_t y) {
        for (int x = 0; x < width; ++x) {
            const ProbeHit& centre = centres[size_t(y - c0) * w + size_t(x)];
            bool differs = false;
            for (int dy = -1; dy <= 1 && !differs; ++dy)
                for (int dx = -1; dx <= 1 && !differs; ++dx) {
                    const int nx = x + dx, ny = int(y) + dy;
                    if ((dx == 0 && dy == 0) || nx < 0 || nx >= width || ny < c0 || ny >= c1)
                        continue;
                    differs = probesDiffer(centre, centres[size_t(ny - c0) * w + size_t(nx)]);
                }
            for (int cy = 0; cy <= 1 && !differs; ++cy)
                for (int cx = 0; cx <= 1 && !differs; ++cx)
                    differs = probesDiffer(
                        centre, corners[size_t(y - rows.ybegin + cy) * (w + 1) + size_t(x + cx)]);
            refine[size_t(y - rows.ybegin) * w + size_t(x)] = differs;
        }
    });
    return refine;
}

} // namespace dhdr
