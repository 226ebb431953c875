// How many pixels the à-trous filter (denoise.h) works on at once: 8 with AVX2, else 4. The
// result is the same bits either way (test_shadows checks it); only the time differs.
#pragma once

#include <dhdr/deferred/denoise/denoise_inputs.h>

namespace dhdr {

// 8 when this CPU has AVX2 and DHDR_EMBREE_ISA (ray_caster.h) asks for no narrower kernel
// than avx2, so that the per-kernel test runs exercise both widths; else 4.
int atrousLanes();

// atrousFilter on `lanes` (4 or 8) pixels at once; 8 on a CPU without AVX2 runs 4.
void atrousFilterLanes(const std::vector<DenoiseEstimate>& estimates, const DenoiseGuide& guide,
                       int nthreads, int lanes);

} // namespace dhdr
