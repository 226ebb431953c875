// What one strip of a frame hands the next in the lighting pass (lighting.h's strip rule).
#pragma once

#include <memory>

namespace dhdr {

// The Monte Carlo estimates a strip traced (environment shadow sums, AO, a catcher's bounce light,
// the specular indirect light) in its last rows, before filtering, handed to the next strip of
// the same frame, which holds those rows as the halo above its own: they are not traced again.
// The same bits as tracing them again (every sequence depends only on the pixel); one carry per
// frame, passed to its strips in order (LightingInputs::carry). Opaque.
class EstimateCarry {
public:
    EstimateCarry();
    ~EstimateCarry();
    EstimateCarry(const EstimateCarry&) = delete;
    EstimateCarry& operator=(const EstimateCarry&) = delete;
    struct Rows; // filtered_estimates.cpp
    std::unique_ptr<Rows> rows;
};

} // namespace dhdr
