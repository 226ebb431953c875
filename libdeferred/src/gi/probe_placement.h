// Placing a probe volume's probes, the bake's first stage (probe_bake.cpp): the grid over the
// scene's bounds, then each probe moved out of walls and away from surfaces, or switched off.
#pragma once

#include <dhdr/deferred/gi/probes.h>
#include <string>

namespace dhdr {

class RayCaster;
struct Scene;

// The grid over `scene`'s bounds for `params` (counts, spacing, origin, the rays per probe),
// its outer layers kProbeInset spacings inside them; false with `error` where it would hold
// too many probes.
bool layOutProbeGrid(const Scene& scene, const ProbeBakeParams& params, ProbeVolume& v,
                     std::string& error);

// Each of `v`'s probes at its grid point where that is free space, else at the nearest free
// point within half a cell (Relocated), else Off.
void placeProbes(const Scene& scene, const RayCaster& caster, const ProbeBakeParams& params,
                 ProbeVolume& v, int nthreads);

} // namespace dhdr
