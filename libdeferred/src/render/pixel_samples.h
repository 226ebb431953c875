// Which pixels of a G-buffer take several primary rays (GBufferParams::samples): those whose
// centre ray sees another surface than a neighbour's centre ray or one of its own corners' —
// an edge, a crease, a step in depth, something thinner than a pixel. Elsewhere one ray through
// the centre gives today's pixel, bit for bit.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

namespace dhdr {

// What a probe ray saw: its first surface (a Blend surface too; Mask cut-outs are holes).
struct ProbeHit {
    bool hit = false;
    int object = -1, material = -1;
    glm::dvec3 position{0.0};
    glm::dvec3 normal{0.0}; // the triangle's, unit length
};

// Whether two probes a pixel or less apart see different surfaces: one hits and the other
// does not, other objects or materials, normals more than 25° apart, or the step between them
// leaves either one's plane by more than a quarter of its length (≈ 14°): a fold or a gap in
// depth. The margins are wide so that a kernel's last bits seldom decide (and when they do, a
// pixel only takes more rays than it needs).
bool probesDiffer(const ProbeHit& a, const ProbeHit& b);

// One flag a pixel of `rows` (whole rows of a width × height frame), row after row: 1 where
// the pixel takes several rays. `probe` traces the ray through an image position (pixels from
// the top-left corner); it is called from `nthreads` threads.
std::vector<std::uint8_t> pixelsToRefine(OIIO::ROI rows, int width, int height,
                                         const std::function<ProbeHit(double, double)>& probe,
                                         int nthreads);

} // namespace dhdr
