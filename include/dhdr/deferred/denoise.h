// Edge-avoiding à-trous wavelet filtering (Dammertz, Sewtz, Hanika & Lensch 2010; the spatial
// part of Schied et al. 2017's SVGF) of per-pixel Monte Carlo estimates, guided by the
// G-buffer: what the lighting pass filters before it divides shadowed by unshadowed light.
#pragma once

#include <glm/glm.hpp>
#include <vector>

namespace dhdr {

// Iterations of the filter (steps 1, 2, 4, 8, 16 pixels) and how far it reaches: a pixel's
// result depends on the pixels within kDenoiseReach rows and columns of it (the taps' 31, and
// the first variance estimate's 5 × 5 reaches one pixel further).
inline constexpr int kDenoiseIterations = 5;
inline constexpr int kDenoiseReach = 2 + 2 + 4 + 8 + 16;

// What tells surfaces apart, per pixel of a width × height image (row-major).
struct DenoiseGuide {
    int width = 0, height = 0;
    std::vector<glm::vec3> position, normal; // world space; normal unit
    std::vector<float> object;               // id.object; pixels of other objects never mix
    std::vector<unsigned char> surface;      // 0: background, never read or written
    // The rows whose results are read, [firstRow, endRow) (endRow < 0: all): each pass runs
    // only on the rows those results depend on, and the other rows keep their input values
    // (a strip's halo, read for its neighbours, is not filtered to the end).
    int firstRow = 0, endRow = -1;
};

// Filters `planes` in place: one plane (an estimate, such as AO) or two (the sums of a ratio
// estimate, shadowed and unshadowed light, filtered alike so that their ratio stays one;
// Heitz, Hill & McGuire 2018), width × height values each, one after the other.
// kDenoiseIterations passes of the 3 × 3 B-spline kernel (1/4, 1/2, 1/4) with holes of 2^i
// pixels (Dammertz et al. 2010 use the 5 × 5 B3-spline in four passes: as clean on our skies,
// at 2.2× the taps; bench/README.md, session 13), each tap weighted by
//   - the normals' agreement, max(0, n_p · n_q)^64;
//   - how far q lies off p's tangent plane for its distance, exp(−(|n_p · (P_q − P_p)| /
//     (0.05 |P_q − P_p|))²): a crease or a step in depth stops the filter, a curved surface
//     seen at a few pixels' distance does not;
//   - the same object;
//   - the estimate itself (the ratio, or the value), exp(−|s_p − s_q| / (4 σ_p)), σ_p its
//     standard deviation: first from p's 5 × 5 neighbourhood of the same surface, then
//     filtered along with it (Schied et al. 2017, SVGF's variance guidance): noise is
//     averaged, a real change in the estimate (a contact shadow) is kept.
// Deterministic and independent of `nthreads`: every pass reads the previous one only.
void atrousFilter(std::vector<float>& planes, int count, const DenoiseGuide& guide,
                  int nthreads = 0);

// Several estimates filtered in one go, each exactly as atrousFilter above filters it alone:
// the guide's weights (normals, plane, object; most of the cost) are computed once a tap for
// all of them, the variance guidance per estimate.
struct DenoiseEstimate {
    std::vector<float>* planes = nullptr;
    int count = 1; // 1 or 2 planes, as above
    // Optional, for an estimate that depends on a direction per pixel (a glossy lobe's
    // visibility): the direction (unit) and its angular width σ (radians) per pixel; a tap
    // is further weighted by exp(−(1 − d_p · d_q) / σ_p²) ≈ exp(−θ² / (2 σ_p²)), so that a
    // narrow lobe mixes only pixels that look the same way.
    const std::vector<glm::vec3>* direction = nullptr;
    const std::vector<float>* width = nullptr;
    // Optional: the pixels where the estimate exists (non-zero); the others keep their values
    // and the filter spends nothing on them (an estimate of a few objects' pixels).
    const std::vector<unsigned char>* active = nullptr;
    // Filter only within reach of where the estimate is unsettled (a pair's sums differ, a
    // single value is not 0); elsewhere it is left as it is. The pairs' ratios and the single
    // values are the same bits either way (a pair's sums there are not: read its ratio).
    bool skipSettled = true;
};
void atrousFilter(const std::vector<DenoiseEstimate>& estimates, const DenoiseGuide& guide,
                  int nthreads = 0);

// exp(x) for x ≤ 0 (1 above, 0 below −87) within 3·10⁻⁷ relative: the filter's weights, in
// plain float arithmetic so that every CPU computes the same bits.
float expNegative(float x);

} // namespace dhdr
