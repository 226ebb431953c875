// Edge-avoiding à-trous wavelet filtering (Dammertz, Sewtz, Hanika & Lensch 2010; the spatial
// part of Schied et al. 2017's SVGF) of per-pixel Monte Carlo estimates, guided by the
// G-buffer: what the lighting pass filters before it divides shadowed by unshadowed light.
#pragma once

#include <dhdr/deferred/denoise/denoise_inputs.h>
#include <vector>

namespace dhdr {

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
void atrousFilter(const std::vector<DenoiseEstimate>& estimates, const DenoiseGuide& guide,
                  int nthreads = 0);

// exp(x) for x ≤ 0 (1 above, 0 below −87) within 3·10⁻⁷ relative: the filter's weights, in
// plain float arithmetic so that every CPU computes the same bits.
float expNegative(float x);

} // namespace dhdr
