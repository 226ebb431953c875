// What the à-trous filter (denoise.h) takes in: the guide that tells surfaces apart, the
// estimates to filter, and how far the filter reaches. Apart from the filter's functions so
// that its private buffers and lanes read them without including the filter.
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

// An estimate for atrousFilter(estimates, …) (denoise.h): its planes and what guides it.
struct DenoiseEstimate {
    std::vector<float>* planes = nullptr;
    int count = 1; // 1 plane or 2 (a ratio estimate's sums), as atrousFilter(planes, …)
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

} // namespace dhdr
