#pragma once
// The GGX-prefiltered levels of an environment (bakeIbl): a deterministic quadrature over the
// sky's mips, with its brightest texels added exactly as points.

#include <atomic>
#include <dhdr/deferred/environment/environment.h>
#include <glm/glm.hpp>
#include <vector>

namespace dhdr {

// A texel brighter than the prefilter's cap (prefilterSource), and the radiance above it.
struct BrightTexel {
    int x, y;
    glm::vec3 rest;
};

// What the levels are prefiltered from: mips of the sky with its bright texels capped, at a
// power-of-two width, and the capped rest in the sky's own grid. References `sky` and, when
// nothing needed capping or resampling, `skyMips`: both must outlive it.
struct PrefilterSource {
    const EnvironmentImage* sky = nullptr;
    std::vector<BrightTexel> bright;
    std::vector<EnvironmentImage> ownMips;
    const std::vector<EnvironmentImage>* mips = nullptr;
};

// `skyMips`: the sky's mip chain down to 32 × 16, the sky first.
PrefilterSource prefilterSource(const EnvironmentImage& sky,
                                const std::vector<EnvironmentImage>& skyMips);

// One prefiltered level, `width` × width / 2, for `roughness`; `cell` is iblLevelCellSize.
// The same bits at any thread count. Rows are skipped once `cancel` (may be null) is set.
EnvironmentImage prefilter(const PrefilterSource& source, int width, float roughness, double cell,
                           int nthreads, const std::atomic<bool>* cancel = nullptr);

} // namespace dhdr
