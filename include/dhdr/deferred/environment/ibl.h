// Image-based lighting (docs/ibl.md): an environment pre-integrated for the split-sum
// approximation, as Filament's cmgen bakes it.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <dhdr/common/param_table.h>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/environment/environment.h>
#include <dhdr/deferred/environment/sun.h>
#include <string>
#include <vector>

namespace dhdr {

struct IblBakeParams {
    // Prefiltered levels, roughness k / (levels − 1) at level k; 2–16. Level 0 is the
    // environment itself (a mirror).
    int levels = 6;
    // Width of level 1, texels (halved at each level after it down to 64, or level 1's width
    // if that is less: iblLevelWidth); 8–4096.
    int baseWidth = 256;
    // How finely level 1's quadrature cuts the lobe, in the GGX importance samples per texel it
    // replaced (cost and cells per texel grow with it; iblLevelCellSize); 1–65536. Each later
    // level takes 4× as many, up to 16× (iblLevelSamples).
    int samples = 128;
    // Side of the DFG table and samples per entry.
    int dfgSize = 128;
    int dfgSamples = 1024;
    // Luminance above which texels are split off as the environment's sun (sun.h), in the
    // image's units; [0, ∞), 0: never.
    float sunThreshold = kDefaultSunThreshold;
    // Set by another thread (the Python module's Ctrl-C) to stop the bake at its next row; it
    // then fails with "cancelled". Null: never.
    const std::atomic<bool>* cancel = nullptr;
};

// IblBakeParams' ranges, and the options of dhdr-ibl and keywords of dhdr.bake_ibl() that set
// them.
inline constexpr IntParam<IblBakeParams> kIblBakeParamTable[] = {
    {"--levels", &IblBakeParams::levels, 2, 16, "N", "prefiltered levels, roughness 0 to 1",
     "levels"},
    {"--base-width", &IblBakeParams::baseWidth, 8, 4096, "W",
     "width of level 1; each later level is half as wide, down to 64", "base_width"},
    {"--samples", &IblBakeParams::samples, 1, 65536, "N",
     "how finely level 1's quadrature cuts the lobe, in the GGX samples per texel it replaced "
     "(cost grows with it); each later level takes 4x as many, up to 16x",
     "samples"},
    {"--dfg-size", &IblBakeParams::dfgSize, 2, 1024, "N", "side of the DFG table", "dfg_size"},
    {"--dfg-samples", &IblBakeParams::dfgSamples, 1, 65536, "N", "samples per DFG entry",
     "dfg_samples"},
};
inline constexpr FloatParam<IblBakeParams> kIblBakeFloatTable[] = {
    {"--sun-threshold",
     "sun_threshold",
     &IblBakeParams::sunThreshold,
     {0.0, 1e30},
     "Y",
     "luminance above which the texels around the brightest one are split off as the "
     "environment's sun, a directional light of its own with its angle (as Blender EEVEE's "
     "world Sun Threshold; 0: keep the sun in the sky)"},
};

// Importance sampling of an environment by its luminance (pbrt-v4's piecewise-constant 2D
// distribution over an equirectangular image, each texel's weight its luminance times its
// solid angle), for environment shadow rays.
struct EnvironmentSampler {
    // One bucket of an alias table (Walker; Vose's construction): keep it with probability
    // keep / 65536, else take `alias`. Four bytes a bucket, and a 256×128 table, keep the
    // buckets and texels (640 KiB) within a core's L2 cache: a sample's random lookups were
    // most of its cost with wider entries or a 512×256 table.
    struct Bucket {
        std::uint16_t keep = 0xffff;
        std::uint16_t alias = 0;
    };
    // What a sample that lands in a texel returns.
    struct Texel {
        glm::vec3 radiance{0.0f};
        float pdf = 0.0f; // density per steradian of directions within this texel
    };
    int width = 0, height = 0;
    double total = 0.0;               // Σ luminance · solid angle over the texels
    std::vector<Bucket> rows;         // the rows, weighted by their share of `total`
    std::vector<Bucket> buckets;      // per row, its texels weighted by luminance · solid angle
    std::vector<Texel> texels;        // width × height
    std::vector<float> rowCos;        // cos θ at the rows' edges, height + 1
    std::vector<glm::vec2> columnPhi; // cos φ and sin φ at the columns' left edges

    void build(const EnvironmentImage& env);
    bool empty() const { return !(total > 0.0); }
    // A direction (in the environment's frame) for u in [0, 1)², with its density per
    // steradian and the radiance of the texel it lies in.
    glm::vec3 sample(glm::vec2 u, float& pdf, glm::vec3& radiance) const;
    // The density sample() draws direction d (unit, the environment's frame) with, and the
    // radiance it returns there: for directions drawn another way (MIS).
    float lookup(const glm::vec3& d, glm::vec3& radiance) const;
};

// The baked environment.
struct Ibl {
    IblBakeParams params;
    // Irradiance as 9 spherical harmonics (bands 0–2) per colour, already convolved with the
    // clamped cosine (Ramamoorthi & Hanrahan 2001): E(n) = Σ sh[i] · Y_i(n).
    std::array<glm::vec3, 9> sh{};
    // Prefiltered radiance per level (level 0: the environment at full resolution).
    std::vector<EnvironmentImage> levels;
    // The split-sum DFG table, dfgSize² entries indexed [roughness][N·V] (texel centres):
    // x = ∫ f/F · cos · (1 − v·h)⁵, y = ∫ f/F · cos (Karis 2013 with the multiple-scattering
    // form of Fdez-Agüera 2019): specular = F0 · (y − x) + x, and y is the single-scattering
    // albedo of a white metal.
    std::vector<glm::vec2> dfg;
    // Built from level 0 at most 256 wide, when the IBL is baked or loaded.
    EnvironmentSampler sampler;
    // The sun split off before the bake (not found() when there was none): the SH, the levels
    // and the sampler hold the sky without it.
    EnvironmentSun sun;
    // Baked from a raw image when it was loaded (readLightsFile), not read from dhdr-ibl's file.
    bool bakedOnLoading = false;

    glm::vec3 irradiance(const glm::vec3& n) const;
    // Prefiltered radiance along R at a roughness, between the two nearest levels by lobe
    // width (α = roughness²).
    glm::vec3 prefiltered(const glm::vec3& R, float roughness) const;
    glm::vec2 dfgAt(float NdotV, float roughness) const;
};

// The roughness prefiltered level k of `levels` holds: k / (levels − 1).
inline float iblLevelRoughness(int k, int levels) {
    return float(k) / float(levels - 1);
}

// The samples of prefiltered level k ≥ 1: params.samples × 4^(k−1), at most 16 ×
// params.samples (128, 512, 2048, 2048, 2048 by default).
inline int iblLevelSamples(const IblBakeParams& params, int k) {
    return int((long long)params.samples << (2 * std::clamp(k - 1, 0, 2)));
}

// The cells of level k's quadrature (bakeIbl) are at most this × (2α + their distance from the
// lobe's centre) wide: 0.25 √(128 / iblLevelSamples), 0.25, 0.125, 0.0625 … by default (about
// 900–2600 cells a texel). Against brute force (bench/prefilter_error.cpp), level 1 at 0.125
// instead gained 0.1 point of mean error on four of the HDRIs for 3× its cells.
inline double iblLevelCellSize(const IblBakeParams& params, int k) {
    return 0.25 * std::sqrt(128.0 / double(iblLevelSamples(params, k)));
}

// The width of prefiltered level k ≥ 1: params.baseWidth / 2^(k−1), but not below 64 (nor
// above level 1's width): read bilinearly between its texels, a 16 × 8 level at roughness 1
// was 1.9–2.5 % off on average (p95 5.8–8.9 %) where its texel centres were within 0.5 %.
inline int iblLevelWidth(const IblBakeParams& params, int k) {
    return std::max(std::min(64, params.baseWidth), params.baseWidth >> std::clamp(k - 1, 0, 30));
}

// The 9 real spherical harmonics Y_0^0 … Y_2^2 at a unit direction.
std::array<float, 9> shBasis(const glm::vec3& d);

// Bakes `env` (in its own frame; a light's rotation turns directions at shading) into `ibl`,
// its sun split off first (params.sunThreshold, ibl.sun). Deterministic: the same result for
// any `nthreads`. False with `error` on bad parameters.
bool bakeIbl(const EnvironmentImage& env, const IblBakeParams& params, Ibl& ibl, std::string& error,
             int nthreads = 0);

// Writes `ibl` as one EXR: subimage k is prefiltered level k ("specular" with its roughness
// in dhdr:roughness), the last subimage the DFG table; the SH coefficients (dhdr:irradianceSH,
// 27 floats) and the bake's parameters are in every header.
bool writeIbl(const std::string& path, const Ibl& ibl, std::string& error);

// Reads an environment for lighting: a file written by writeIbl as it is, or any 2:1 image,
// baked here with `params`. `baked` says which it was; `replaced` counts NaN/Inf texels.
bool loadIbl(const std::string& path, const IblBakeParams& params, Ibl& ibl, bool& baked,
             std::string& error, long long* replaced = nullptr, int nthreads = 0);

// How an environment's specular light is computed: the split sum (prefiltered levels × DFG;
// Karis 2013), which assumes N = V = R and misses the stretched, off-specular lobe of rough
// surfaces seen at grazing angles; a quadrature of the exact single-scattering lobe; or
// (Auto) the quadrature from kIblQuadratureRoughness up and the split sum below, where it is
// accurate.
enum class IblSpecular { Auto, SplitSum, Quadrature };
inline constexpr float kIblQuadratureRoughness = 0.3f;
inline constexpr int kIblQuadratureSamples = 32;

// The single-scattering GGX reflection of the environment towards V, F0 (y − x) + x's
// counterpart: filtered importance sampling (Křivánek & Colbert 2008) as a deterministic
// stratified sum: `samples` directions from GGX's visible normals (Heitz 2018) on a fixed
// Hammersley set, each weighted by F · G2 / G1 (the exact f cos / pdf) and reading the
// environment at the mip whose texels match the sample's solid angle 1 / (samples · pdf); the
// weighted mean radiance times the lobe's albedo from the DFG table, F0 (y − x) + x.
glm::vec3 specularQuadrature(const Ibl& ibl, const PbrSurface& s, const glm::vec3& N,
                             const glm::vec3& V, int samples = kIblQuadratureSamples);

// Light reflected towards V from an environment seen through `ibl`: diffuse =
// c_diff · E(n) / π, specular = prefiltered(R, roughness) · (F0 (y − x) + x) + the
// multiple-scattering lobe's albedo · E(n) / π (multiple_scattering.h).
struct IblShading {
    glm::vec3 diffuse{0.0f}, specular{0.0f};
};
// With IblSpecular::Quadrature (or Auto at high roughness) the first specular term is
// specularQuadrature's. `spread` (radians, ≥ 0) is the angle the mirror directions of the
// pixel's footprint span (reflectionSpread in integrator/shade_sample.cpp; 0: a point): the split
// sum reads the levels at the lobe widened by it, α' = √(α² + (kFootprintAlpha · spread)²), so that
// a mirror shows the sky filtered over its pixel instead of one point of it. Matching GGX's half
// width at half maximum (1.29 α) to half the spread gives 0.39, which over-blurs (the lobe's
// long tail); measured against a supersampled mirror
// (EnvironmentReflections.AMirrorShowsTheSkyFilteredOverItsPixel), 0.12 / 0.18 / 0.25 / 0.39 /
// 0.6 leave a mean error of 0.132 / 0.108 / 0.106 / 0.142 / 0.162.
inline constexpr float kFootprintAlpha = 0.25f;
IblShading shadeIbl(const Ibl& ibl, const PbrSurface& s, const glm::vec3& N, const glm::vec3& V,
                    IblSpecular method = IblSpecular::Auto, float spread = 0.0f);

// Specular occlusion from ambient occlusion (Lagarde & de Rousiers 2014, "Moving Frostbite to
// PBR", eq. 51): saturate((N·V + ao)^(2^(−16 roughness − 1)) − 1 + ao); 1 where ao is 1.
float specularOcclusion(float NdotV, float ao, float roughness);

} // namespace dhdr
