// The pixel filter a G-buffer's primary rays are drawn from (docs/gbuffer.md, "Samples and the
// pixel filter"): each ray's offset from the pixel's centre follows the filter, so that the
// pixel's value is the plain mean of its rays' (filter importance sampling, as Cycles does),
// and no ray reaches into another pixel's sum.
#pragma once

#include <glm/glm.hpp>
#include <vector>

namespace dhdr {

enum class PixelFilter { Box, Gaussian, BlackmanHarris };

// The filter along one axis at x pixels from the centre, `width` pixels wide in all (zero
// beyond ±width/2), not normalised; the 2-D filter is the product of both axes'.
// Blackman–Harris is Cycles' (film.cpp); the Gaussian has σ = width / 6, less its value at the
// edge (pbrt-v4's; width 3 is pbrt's radius 1.5, σ 0.5); the box is 1.
double pixelFilterValue(PixelFilter filter, double width, double x);

// Offsets drawn from a filter by its inverse cumulative distribution, tabulated once.
class PixelFilterSampler {
public:
    PixelFilterSampler(PixelFilter filter, float width);
    // The offset from the centre, in pixels, at probability u ∈ [0, 1): monotone in u, so
    // stratified u give stratified offsets.
    float offset(float u) const;
    // Ray k of the n × n stratified rays of pixel (x, y): its offset from the pixel's centre,
    // jittered within its stratum by a hash of (x, y, k) alone.
    glm::vec2 rayOffset(int x, int y, int k, int n) const;

private:
    std::vector<float> m_inverse; // offset at u = i / (size − 1)
};

} // namespace dhdr
