// Arguments of the precomputed tables (albedo, DFG, prefiltered levels, environment texels)
// clamped before they become indices: a NaN or infinite cosine or coordinate, from a normal
// that could not be normalised or a corrupt file, reads an end of the table, never past it.
#pragma once

#include <algorithm>
#include <cmath>

namespace dhdr {

// `v` within [lo, hi], NaN as `lo`: std::clamp passes NaN through, and int(NaN) is undefined
// (INT_MIN on x86, an index far outside any table).
inline float clampForTable(float v, float lo, float hi) {
    return std::isnan(v) ? lo : std::clamp(v, lo, hi);
}

} // namespace dhdr
