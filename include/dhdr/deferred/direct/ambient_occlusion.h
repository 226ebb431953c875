// Ambient occlusion: how open the hemisphere above a surface point is, by ray tracing the
// scene or from the G-buffer alone (screen space).
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <cstdint>
#include <dhdr/common/param_table.h>
#include <dhdr/deferred/core/visibility.h>

namespace dhdr {

// The share of `samples` cosine-weighted rays (a Hammersley set rotated by `seed`) from the
// surface point `at` about its shading normal N that meet nothing within `distance` (scene
// units; +∞: any distance). 1 on an open plane; it weighs directions as diffuse light does, so
// a floor beside an infinite wall gets ½. Each ray starts at offsetRayOrigin(at, direction).
// Directions below the triangle's own plane (at.Ng; a smooth normal at a silhouette leans
// past it) are left out of the share; with none left, 1. `rays` (optional) counts the rays
// traced.
float rayTracedOcclusion(const SurfacePoint& at, const glm::vec3& N, std::uint64_t seed,
                         int samples, float distance, const Visibility& visibility,
                         long long* rays = nullptr);

// Screen-space ambient occlusion (Crytek's SSAO with a normal-oriented hemisphere, as the
// seed on virtual-real fusion uses it).
struct SsaoParams {
    // Radius of the hemisphere kernel, scene units (metres); > 0.
    float radius = 0.5f;
    // Kernel points per pixel (range: kSsaoParamTable); each pixel of a 4 × 4 block turns the
    // kernel about its normal by a different angle, and the 4 × 4 blur averages the 16 turns.
    int samples = 16;
    // Depth a kernel point must be behind the stored surface to count as occluded, scene
    // units; absorbs the G-buffer's depth precision.
    float bias = 0.005f;
};

// SsaoParams' counts: dhdr-light's --ao-samples with --ao ssao.
inline constexpr IntParam<SsaoParams> kSsaoParamTable[] = {
    {"--ao-samples", &SsaoParams::samples, 1, 256, "N", "--ao ssao: kernel points per pixel",
     "ao_samples"},
};

// One channel "AO" in [0, 1] for every pixel of `gbuffer` (a whole frame, float or not; 1
// where there is no surface). A kernel point occludes when the G-buffer's surface at its
// pixel lies in front of it; the range check fades occluders farther from the point than the
// radius (smoothstep(0, 1, radius / |Δdepth|)); then a 4 × 4 box blur over covered pixels.
// Errors (not a G-buffer, no camera) are reported on `dst`.
bool screenSpaceAO(OIIO::ImageBuf& dst, const OIIO::ImageBuf& gbuffer, const SsaoParams& params,
                   int nthreads = 0);

} // namespace dhdr
