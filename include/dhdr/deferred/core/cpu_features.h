// What this CPU runs, asked once where a choice depends on it: the Embree kernel the ray
// casters use and the denoiser's vector width (tests run the suite under each).
#pragma once

#include <string>

namespace dhdr {

// The Embree kernel that RayCasters use: the environment variable DHDR_EMBREE_ISA (sse2,
// sse4.2, avx, avx2 or avx512), empty for Embree's own choice (the widest the CPU has). It also
// keeps the denoiser to 4 lanes below avx2 (denoise/denoise_lanes.h; the same bits either way).
std::string embreeIsaRequested();
// Whether this CPU runs Embree's kernel `isa` (one of the names above).
bool embreeIsaSupported(const std::string& isa);

} // namespace dhdr
