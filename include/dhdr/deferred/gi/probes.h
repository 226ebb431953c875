// Light probes for diffuse global illumination (docs/gi.md), after Majercik et al. 2019,
// "Dynamic Diffuse Global Illumination with Ray-Traced Irradiance Fields" (DDGI), baked once
// for a static scene: a grid of probes, each moved out of walls or switched off, each holding
// an octahedral map of the irradiance arriving at it and one of the distance to the nearest
// surface (mean and mean of squares), from which shading interpolates the 8 probes around a
// point weighted so that light does not leak through walls.
#pragma once

#include <atomic>
#include <dhdr/common/param_table.h>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/gbuffer/gbuffer_time.h>
#include <dhdr/deferred/scene/lights.h>
#include <dhdr/io/sanitize.h>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace dhdr {

class RayCaster;
class Visibility;
struct Scene;
struct ShadowRay;

struct ProbeBakeParams {
    // Metres (scene units) between probes at most, ≥ 0 (each axis's is the largest up to it that
    // puts its outer layers kProbeInset spacings inside the bounds); 0: the smallest spacing
    // that covers the scene's bounds with at most maxProbes probes (probeSpacingFor). Unused
    // with counts.
    double spacing = 0.0;
    glm::ivec3 counts{0}; // probes along X, Y, Z (kProbeGridTable); 0: from `spacing`
    // The counts: their meaning and ranges are kProbeBakeParamTable's (validated by bakeProbes).
    int maxProbes = 512;
    int rays = 256;
    int bounces = 0; // 0: until the irradiance converges (kProbeConvergence)
    int shadowSamples = 4;
    DiffuseModel diffuse = DiffuseModel::Lambert; // of every surface the rays meet (brdf.h)
    float backfaceLimit = 0.25f; // a probe seeing more back faces than this share is inside
    float minDistance = 0.1f;    // … or nearer a surface than this × spacing: moved or off
    // Called with the share of the work done, in [0, 1], from the calling thread, after the
    // rays and after each bounce.
    std::function<void(float)> progress;
    // Set from another thread to stop early (dhdr.bake_probes on Ctrl-C): probes not begun are
    // left out and bakeProbes returns false ("interrupted"), the volume to be thrown away.
    const std::atomic<bool>* cancel = nullptr;
};

// ProbeBakeParams' counts, and the options of dhdr-probes that set them.
inline constexpr IntParam<ProbeBakeParams> kProbeBakeParamTable[] = {
    {"--max-probes", &ProbeBakeParams::maxProbes, 1, 262144, "N",
     "without --spacing or --grid: the spacing that covers the scene's bounds with at most N "
     "probes",
     "max_probes"},
    {"--rays", &ProbeBakeParams::rays, 16, 65536, "N", "rays per probe: a spherical Fibonacci set",
     "rays"},
    {"--bounces", &ProbeBakeParams::bounces, 0, 64, "K",
     "light bounces (0: until what further bounces would add is under 0.5 % of the light)",
     "bounces"},
    {"--shadow-samples", &ProbeBakeParams::shadowSamples, 1, 256, "N",
     "shadow rays per area light at each ray's hit", "shadow_samples"},
};

// The most probes along an axis.
inline constexpr int kMaxProbesPerAxis = 256;

// ProbeBakeParams' spacing and grid, and the options of dhdr-probes and keywords of
// dhdr.bake_probes() that set them.
inline constexpr FloatParam<ProbeBakeParams, double> kProbeBakeFloatTable[] = {
    {"--spacing",
     "spacing",
     &ProbeBakeParams::spacing,
     {0.0, 1e6},
     "M",
     "distance between probes in scene units, at most (each axis's is the largest that puts the "
     "outer probes a quarter spacing inside the scene's bounds); 0, the default: from the bounds "
     "and --max-probes"},
};
inline constexpr IntVecParam<ProbeBakeParams, glm::ivec3> kProbeGridTable[] = {
    {"--grid", "grid", &ProbeBakeParams::counts, 1, kMaxProbesPerAxis, "NX,NY,NZ",
     "probe counts along X, Y, Z instead of --spacing"},
};

// The grid's outer layers stand this many spacings inside the scene's bounds, where a room's
// walls are: near enough that a wall's irradiance is read close to it (and extrapolated a
// quarter spacing), far enough (over minDistance) that a probe in a corner is not moved.
// Centred layers (half a spacing in) read the real-scale Cornell box's corners 15-25 % bright
// (docs/gi.md, "Placement").
inline constexpr double kProbeInset = 0.25;

// The smallest spacing (within 1 %) at which a grid over a box of `extent` holds at most
// `maxProbes` probes (max(1, ⌈extent / spacing + 1 − 2 kProbeInset⌉) along each axis, at most
// kMaxProbesPerAxis), so that a scene gets the same number of probes at any scale.
double probeSpacingFor(const glm::dvec3& extent, int maxProbes);

// Bounces until the light the bounces to come would still add to the sum of every probe's
// irradiance (each adding the same share of the last one's, geometrically) is at most this
// share of it (ProbeBakeParams::bounces 0), and at most kProbeMaxBounces.
inline constexpr double kProbeConvergence = 0.005;
inline constexpr int kProbeMaxBounces = 64;

enum class ProbeState : int {
    Active = 0,    // at its grid point
    Relocated = 1, // moved within half a cell into free space
    Off = 2        // inside geometry with no free space near: not used
};

struct ProbeVolume {
    // Texels of the octahedral maps, without their one-texel borders: DDGI's 14 for the
    // distances, 16 for the irradiance. Near the folded pole the bilinear lookup reads texels
    // up to 36° away at 8 (20° at an axis at DDGI's 6), and a probe whose E(n) dips steeply
    // there (looking out of an opening, or beside a lit surface) reads far above its own E(n):
    // the real-scale Cornell box's short block +10 % at 8, +1 % at 16 (docs/gi.md).
    static constexpr int kIrradianceTexels = 16;
    static constexpr int kDistanceTexels = 14;

    glm::dvec3 origin{0.0};  // grid point (0, 0, 0)
    glm::dvec3 spacing{1.0}; // between grid points, per axis
    glm::ivec3 counts{0};
    int rays = 0, bounces = 0;
    // The diffuse model the bake's hits reflected with (ProbeBakeParams::diffuse); the frame
    // should shade with the same.
    DiffuseModel diffuse = DiffuseModel::Lambert;
    // The moment of an animated scene the bake saw (dhdr-probes --frame, --frames, --time),
    // recorded as a G-buffer records it, so that dhdr-light can tell a probe file baked for
    // another moment than its G-buffer's; none: a still scene (or a file from before).
    std::optional<gbuffer::Moment> moment;
    std::vector<glm::vec3> positions; // per probe (x fastest, then y, then z), relocated
    std::vector<ProbeState> states;
    // Per probe, its bordered maps in scanline order: irradiance E(n) in W/m² per unit of
    // the lights' radiance ((16 + 2)² texels), and the distance moments ((14 + 2)² texels).
    std::vector<glm::vec3> irradiance;
    std::vector<glm::vec2> distance;
    // Distance moments the bake computed as NaN or ±Inf (a scene past float's range) and
    // stored as 0 or ±FLT_MAX, as the tools write any such value (docs/gi.md).
    NonFiniteCount replaced;

    int probeCount() const { return counts.x * counts.y * counts.z; }
    int index(glm::ivec3 g) const { return (g.z * counts.y + g.y) * counts.x + g.x; }
    glm::dvec3 gridPoint(glm::ivec3 g) const { return origin + glm::dvec3(g) * spacing; }

    // Bilinear lookups in probe p's maps for a direction (seamless through the borders).
    glm::vec3 irradianceAt(int p, const glm::vec3& n) const;
    glm::vec2 distanceAt(int p, const glm::vec3& d) const;

    // Irradiance arriving at P (normal N, unit V towards the eye) from the 8 probes around it:
    // trilinear weights × back-face wrap × the probe's visibility, at P moved by the normal and
    // view biases (DDGI §5.2). Visibility is Chebyshev's bound from the distance moments, or,
    // given the scene, a ray to the probe where those moments spread (kProbeTracedSpread). A
    // probe hidden from P gives way to its value extrapolated from the visible probes beyond
    // it (kProbeFillSlope; DDGI's renormalisation takes the visible side's value). Beyond the
    // grid's outer layers (up to half a spacing; the scene's bounds are kProbeInset out),
    // extrapolated linearly. docs/gi.md "Shading".
    glm::vec3 irradianceAt(const glm::vec3& P, const glm::vec3& N, const glm::vec3& V,
                           const Visibility* scene = nullptr) const;

    // What surface s at P reflects of the probes' light towards V: its diffuse layer's albedo ×
    // E(N) / π and, with `specularLobe` (a rough lobe whose light is not traced,
    // kProbeGlossyRoughness), its specular lobe's albedo × E(D) / π, E read in the lobe's
    // dominant direction D (Lagarde & de Rousiers 2014) rather than along N. The frame's
    // pixels and the hits of its secondary rays reflect the probes alike.
    glm::vec3 reflectedAt(const PbrSurface& s, const glm::vec3& P, const glm::vec3& N,
                          const glm::vec3& V, bool specularLobe,
                          const Visibility* scene = nullptr) const;
    // The biases, as fractions of the smallest spacing.
    float normalBias = 0.1f, viewBias = 0.1f;

private:
    // The probes' visibilities from one biased point, kept between the lookups of its cells.
    struct SeenFrom {
        static constexpr int kSize = 16;
        int probe[kSize];
        float visible[kSize];
        int count = 0;
    };
    // The chance that each corner of the cell at grid point `base` sees `biased` (0 for a
    // probe that is off or a corner of trilinear weight 0): Chebyshev's, or where the moments
    // spread, the scene's rays, traced together; from `seen` where it holds the probe.
    void cornerVisibilities(glm::ivec3 base, const double trilinear[8], const glm::vec3& biased,
                            const Visibility* scene, SeenFrom& seen, float visible[8]) const;
    // The weighted mean of the 8 probes around grid coordinates `local` (clamped into the
    // grid), weighted for the point P (normal N), moved off its surface to `biased`.
    glm::vec3 interpolate(const glm::vec3& P, const glm::vec3& N, const glm::vec3& biased,
                          const glm::dvec3& local, const Visibility* scene, SeenFrom& seen) const;
    // Chebyshev's bound on the chance that probe p sees `biased`; with `traced`, also the
    // share of it that the ray `ray` (from `biased` to the probe) should decide instead.
    float chebyshev(int p, const glm::vec3& biased, float* traced, ShadowRay* ray) const;
    // E(N) at grid point g (a corner of the cell whose other corners `offset` points away
    // from), extrapolated from the two probes beyond it along each axis into the cell,
    // E₁ + kProbeFillSlope (E₁ − E₂), averaged with weights N_a² × their visibilities;
    // returns the weights' sum (at most 1; 0: E unset).
    float extrapolated(glm::ivec3 g, glm::ivec3 offset, const glm::vec3& N, const glm::vec3& biased,
                       glm::vec3& E) const;
};

// From this roughness up, a specular lobe reflects the probes' irradiance as its albedo does
// (specularAlbedo × E / π: exact for uniform light, close for a lobe that wide): at a probe
// ray's hit (below it, the lobe is followed along a sampled direction, so that metals show
// the room), and at a shaded point whose specular indirect light is not traced (shade_sample.cpp).
inline constexpr float kProbeGlossyRoughness = 0.5f;

// Where the distance moments towards a point spread, σ / μ from the first to the second (a
// texel holding an edge's near distances and the far ones past it, whose mean lies beyond a
// point the edge hides), a ray to the probe decides its visibility, blended in smoothly.
inline constexpr float kProbeTracedSpread[2] = {0.5f, 0.8f};

// The share of the slope between the two probes beyond a hidden one that its fill carries on
// (ProbeVolume::irradianceAt): 0 takes the neighbour's value, much as DDGI's renormalisation
// does, 1 extrapolates linearly. Near a face the light curves: 1 overshoots (the two rooms'
// divider −5.2 %, the real-scale Cornell box's tall block +4.0 %), 0 falls short (the
// project-scale tall block −5.6 %); ½ keeps every surface of the three within 4.6 % of the
// path tracer (docs/gi.md "Shading").
inline constexpr float kProbeFillSlope = 0.5f;

// Sharpness of the cosine lobe the distance maps average under, max(0, n·ω)^50 (DDGI's).
inline constexpr double kProbeDistanceSharpness = 50.0;

// Direction i of a spherical Fibonacci set of n (Keinert et al. 2015): close to uniform,
// deterministic.
glm::vec3 sphericalFibonacci(int i, int n);

// Bakes a probe volume over the scene's bounds: placement (grid, relocation, switching off),
// then `bounces` rounds of rays from every probe. A ray's hit is lit by `lights` (punctual and
// area lights with shadow rays through `caster`; environments and ambient lights are not
// direct light here), plus its emission when no light stands for it (`emissiveAreLights`
// false), plus the previous round's probe irradiance × diffuseAlbedo / π; a miss sees
// the environment lights' radiance. The result does not depend on `nthreads`. False with
// `error` on bad parameters, an empty scene, or irradiance past float's range.
bool bakeProbes(const Scene& scene, const RayCaster& caster, const std::vector<Light>& lights,
                bool emissiveAreLights, const ProbeBakeParams& params, ProbeVolume& volume,
                std::string& error, int nthreads = 0);

// One EXR with two parts, "irradiance" (RGB) and "distance" (mean, mean²): each an atlas of
// the probes' bordered maps, probe p in column p % cols, row p / cols; the grid, the states
// and the bake's parameters in the header (docs/gi.md).
bool writeProbes(const std::string& path, const ProbeVolume& volume, std::string& error);
bool readProbes(const std::string& path, ProbeVolume& volume, std::string& error);

// The grid's origin and spacing rounded to the floats a probe file stores: a volume baked in
// memory then lights a frame with the same bits as the file dhdr-probes writes of it.
void roundAsStored(ProbeVolume& volume);

} // namespace dhdr
