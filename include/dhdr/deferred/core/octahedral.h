// Octahedral maps of the sphere of directions (Cigolle et al. 2014, "A Survey of Efficient
// Representations for Independent Unit Vectors", §3.3): the sphere projected onto the
// octahedron |x| + |y| + |z| = 1, its lower half folded over the corners of the square.
// The light probes (probes.h) store irradiance and distance in such maps, each with a one-texel
// border copied from the opposite edges, so that bilinear filtering is seamless (Majercik et
// al. 2019, "Dynamic Diffuse Global Illumination with Ray-Traced Irradiance Fields", §4).
#pragma once

#include <cmath>
#include <glm/glm.hpp>

namespace dhdr {

inline float signNotZero(float v) {
    return v >= 0.0f ? 1.0f : -1.0f;
}

// A unit direction to [−1, 1]².
inline glm::vec2 octEncode(const glm::vec3& d) {
    const glm::vec2 p = glm::vec2(d.x, d.y) / (std::abs(d.x) + std::abs(d.y) + std::abs(d.z));
    if (d.z >= 0.0f) return p;
    return {(1.0f - std::abs(p.y)) * signNotZero(p.x), (1.0f - std::abs(p.x)) * signNotZero(p.y)};
}

// The inverse of octEncode: [−1, 1]² to a unit direction.
inline glm::vec3 octDecode(glm::vec2 e) {
    glm::vec3 v(e.x, e.y, 1.0f - std::abs(e.x) - std::abs(e.y));
    if (v.z < 0.0f) {
        const float x = v.x;
        v.x = (1.0f - std::abs(v.y)) * signNotZero(x);
        v.y = (1.0f - std::abs(x)) * signNotZero(v.y);
    }
    return glm::normalize(v);
}

// The border texel (bx, by) of an n × n map with a one-texel border ((n + 2)² texels, interior
// 1 … n): the interior texel whose value it copies. Edges copy the texel mirrored across the
// edge's midpoint on the same edge, corners the opposite interior corner; the octahedron's
// folds make those the neighbours across the border.
inline glm::ivec2 octBorderSource(int bx, int by, int n) {
    const int last = n + 1;
    const bool cornerX = bx == 0 || bx == last, cornerY = by == 0 || by == last;
    if (cornerX && cornerY) return {bx == 0 ? n : 1, by == 0 ? n : 1};
    if (by == 0 || by == last) return {n + 1 - bx, by == 0 ? 1 : n};
    return {bx == 0 ? 1 : n, n + 1 - by};
}

} // namespace dhdr
