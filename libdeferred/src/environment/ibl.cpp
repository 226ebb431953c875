#include "environment/prefilter.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/core/brdf_integrals.h>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/core/table_lookup.h>
#include <dhdr/deferred/environment/ibl.h>

namespace dhdr {

namespace {

// The normalization constants of the real SH bands 0–2: 1/(2√π), √3/(2√π), √15/(2√π),
// √5/(4√π), √15/(4√π).
constexpr double kC0 = 0.28209479177387814, kC1 = 0.4886025119029199, kC2 = 1.0925484305920792,
                 kC3 = 0.31539156525252005, kC4 = 0.5462742152960396;

} // namespace

std::array<float, 9> shBasis(const glm::vec3& d) {
    const double x = d.x, y = d.y, z = d.z;
    return {float(kC0),
            float(kC1 * y),
            float(kC1 * z),
            float(kC1 * x),
            float(kC2 * x * y),
            float(kC2 * y * z),
            float(kC3 * (3.0 * z * z - 1.0)),
            float(kC2 * x * z),
            float(kC4 * (x * x - y * y))};
}

namespace {

// ∫ Y_i dω over texel (x, y) of an equirectangular image, in closed form. With θ from +Y and
// φ = 2π (u − ½): x = sin θ cos φ, y = cos θ, z = sin θ sin φ, dω = sin θ dθ dφ.
std::array<double, 9> shTexelIntegrals(const EnvironmentImage& env, int x, int y) {
    const double pi = 3.14159265358979323846;
    const double t0 = pi * y / env.height, t1 = pi * (y + 1) / env.height;
    const double p0 = 2.0 * pi * (double(x) / env.width - 0.5);
    const double p1 = 2.0 * pi * (double(x + 1) / env.width - 0.5);
    const double s0 = std::sin(t0), s1 = std::sin(t1), c0 = std::cos(t0), c1 = std::cos(t1);
    // θ integrals of sin θ · {1, cos θ, sin θ, sin θ cos θ, sin² θ, cos² θ}.
    const double a1 = c0 - c1;
    const double aCos = 0.5 * (s1 * s1 - s0 * s0);
    const double aSin = 0.5 * (t1 - t0) - 0.25 * (std::sin(2 * t1) - std::sin(2 * t0));
    const double aSinCos = (s1 * s1 * s1 - s0 * s0 * s0) / 3.0;
    const double aSin2 = (c1 * c1 * c1 - c0 * c0 * c0) / 3.0 - (c1 - c0); // ∫ sin³
    const double aCos2 = (c0 * c0 * c0 - c1 * c1 * c1) / 3.0;             // ∫ cos² sin
    // φ integrals of {1, cos, sin, cos², sin², sin cos}.
    const double dp = p1 - p0;
    const double bCos = std::sin(p1) - std::sin(p0), bSin = std::cos(p0) - std::cos(p1);
    const double bCos2 = 0.5 * dp + 0.25 * (std::sin(2 * p1) - std::sin(2 * p0));
    const double bSin2 = 0.5 * dp - 0.25 * (std::sin(2 * p1) - std::sin(2 * p0));
    const double bSinCos = 0.5 * (std::sin(p1) * std::sin(p1) - std::sin(p0) * std::sin(p0));
    return {kC0 * a1 * dp,
            kC1 * aCos * dp,
            kC1 * aSin * bSin,
            kC1 * aSin * bCos,
            kC2 * aSinCos * bCos,
            kC2 * aSinCos * bSin,
            kC3 * (3.0 * aSin2 * bSin2 - a1 * dp),
            kC2 * aSin2 * bSinCos,
            kC4 * (aSin2 * bCos2 - aCos2 * dp)};
}

} // namespace

glm::vec3 Ibl::irradiance(const glm::vec3& n) const {
    const std::array<float, 9> Y = shBasis(n);
    glm::vec3 e(0.0f);
    for (int i = 0; i < 9; ++i)
        e += sh[size_t(i)] * Y[size_t(i)];
    return glm::max(e, glm::vec3(0.0f));
}

glm::vec3 Ibl::prefiltered(const glm::vec3& R, float roughness) const {
    const int last = int(levels.size()) - 1;
    const float r = clampForTable(roughness, 0.0f, 1.0f);
    const int k0 = std::min(int(r * float(last)), last);
    const int k1 = std::min(k0 + 1, last);
    const glm::vec2 uv = equirectUV(R);
    const glm::vec3 a = levels[size_t(k0)].bilinear(uv);
    if (k1 == k0) return a;
    // Between the two levels by lobe width, GGX's α = roughness², not by roughness: a
    // roughness of 0.05 is a lobe 1/16 as wide as 0.2's, and took a quarter of its blur.
    const float r0 = iblLevelRoughness(k0, last + 1), r1 = iblLevelRoughness(k1, last + 1);
    const float t = std::clamp((r * r - r0 * r0) / (r1 * r1 - r0 * r0), 0.0f, 1.0f);
    return glm::mix(a, levels[size_t(k1)].bilinear(uv), t);
}

glm::vec2 Ibl::dfgAt(float NdotV, float roughness) const {
    const int n = params.dfgSize;
    const float fx = clampForTable(NdotV, 0.0f, 1.0f) * float(n) - 0.5f;
    const float fy = clampForTable(roughness, 0.0f, 1.0f) * float(n) - 0.5f;
    const int x0 = std::clamp(int(std::floor(fx)), 0, n - 1),
              y0 = std::clamp(int(std::floor(fy)), 0, n - 1);
    const int x1 = std::min(x0 + 1, n - 1), y1 = std::min(y0 + 1, n - 1);
    const float ax = std::clamp(fx - float(x0), 0.0f, 1.0f),
                ay = std::clamp(fy - float(y0), 0.0f, 1.0f);
    auto at = [&](int x, int y) { return dfg[size_t(y) * size_t(n) + size_t(x)]; };
    return glm::mix(glm::mix(at(x0, y0), at(x1, y0), ax), glm::mix(at(x0, y1), at(x1, y1), ax), ay);
}

bool bakeIbl(const EnvironmentImage& source, const IblBakeParams& p, Ibl& ibl, std::string& error,
             int nthreads) {
    if (p.levels < 2 || p.levels > 16 || p.baseWidth < 8 || p.baseWidth > 4096 || p.samples < 1 ||
        p.samples > 65536 || p.dfgSize < 2 || p.dfgSize > 1024 || p.dfgSamples < 1 ||
        p.dfgSamples > 65536 || !(p.sunThreshold >= 0.0f) || !std::isfinite(p.sunThreshold)) {
        error = "IBL bake parameters out of range";
        return false;
    }
    if (source.width != 2 * source.height || source.height < 2) {
        error = "the environment is not a 2:1 equirectangular image";
        return false;
    }
    ibl.params = p;
    // The sky without its sun is what the rest bakes.
    EnvironmentImage env = source;
    ibl.sun = extractSun(env, p.sunThreshold);
    ibl.sampler.build(env);

    // (a) Irradiance SH: project the radiance, each texel's value times the exact integral of
    // every basis function over the texel (so a constant environment projects exactly onto
    // band 0), in double, row by row in a fixed order; then convolve with the clamped cosine:
    // Â = π, 2π/3, π/4.
    std::vector<std::array<glm::dvec3, 9>> rows(size_t(env.height));
    OIIO::parallel_for(
        0, env.height,
        [&](int64_t y) {
            std::array<glm::dvec3, 9> acc{};
            for (int x = 0; x < env.width; ++x) {
                const std::array<double, 9> Y = shTexelIntegrals(env, x, int(y));
                const glm::dvec3 L(env.texel(x, int(y)));
                for (int i = 0; i < 9; ++i)
                    acc[size_t(i)] += L * Y[size_t(i)];
            }
            rows[size_t(y)] = acc;
        },
        perItem(nthreads));
    std::array<glm::dvec3, 9> total{};
    for (const auto& r : rows)
        for (int i = 0; i < 9; ++i)
            total[size_t(i)] += r[size_t(i)];
    const double pi = 3.14159265358979323846;
    const double band[9] = {pi,     2 * pi / 3, 2 * pi / 3, 2 * pi / 3, pi / 4,
                            pi / 4, pi / 4,     pi / 4,     pi / 4};
    for (int i = 0; i < 9; ++i)
        ibl.sh[size_t(i)] = glm::vec3(total[size_t(i)] * band[i]);

    // (b) The prefiltered chain, from a mip pyramid of the environment down to 32 × 16: below
    // that, bilinear reads of a lat-long image are too coarse near the poles (7 % off at
    // roughness 1 with an 8 × 4 level, under 2 % with 32 × 16;
    // Ibl.PrefilteredAgainstBruteForceGgx).
    std::vector<EnvironmentImage> mips = {env};
    while (mips.back().height > 16)
        mips.push_back(mips.back().downsampled());
    const PrefilterSource sky = prefilterSource(env, mips);
    ibl.levels.clear();
    ibl.levels.push_back(env);
    const auto cancelled = [&p] { return p.cancel && p.cancel->load(std::memory_order_relaxed); };
    for (int k = 1; k < p.levels && !cancelled(); ++k)
        ibl.levels.push_back(prefilter(sky, iblLevelWidth(p, k), iblLevelRoughness(k, p.levels),
                                       iblLevelCellSize(p, k), nthreads, p.cancel));

    // (c) The DFG table.
    ibl.dfg.assign(size_t(p.dfgSize) * size_t(p.dfgSize), glm::vec2(0.0f));
    OIIO::parallel_for(
        0, p.dfgSize,
        [&](int64_t j) {
            if (cancelled()) return;
            const float roughness = (float(j) + 0.5f) / float(p.dfgSize);
            const std::vector<glm::vec3> halves = dfgHalfVectors(roughness, p.dfgSamples);
            for (int i = 0; i < p.dfgSize; ++i)
                ibl.dfg[size_t(j) * size_t(p.dfgSize) + size_t(i)] =
                    integrateDFG((float(i) + 0.5f) / float(p.dfgSize), roughness, halves);
        },
        perItem(nthreads));
    if (cancelled()) {
        error = "cancelled";
        return false;
    }
    return true;
}

glm::vec3 specularQuadrature(const Ibl& ibl, const PbrSurface& s, const glm::vec3& N,
                             const glm::vec3& V, int samples) {
    const float NdotV = glm::dot(N, V);
    if (!(NdotV > 0.0f) || samples < 1) return glm::vec3(0.0f);
    const float alpha = s.alpha();
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    const glm::vec3 Vl(glm::dot(V, t), glm::dot(V, b), NdotV);
    const float G1v = smithGgxMasking(NdotV, alpha);
    glm::vec3 sum(0.0f), weight(0.0f);
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 h = sampleGgxVisibleNormal(
            Vl, alpha, hammersley(std::uint32_t(i), std::uint32_t(samples), 0));
        const float VdotH = glm::dot(Vl, h);
        const glm::vec3 l = 2.0f * VdotH * h - Vl;
        if (!(l.z > 0.0f) || !(VdotH > 0.0f)) continue;
        // f cos / pdf = F · G2 / G1(V), with G2 = Vis · 4 (n·l)(n·v).
        const float g2 = smithGgxCorrelatedVisibility(l.z, NdotV, alpha) * 4.0f * l.z * NdotV;
        const glm::vec3 F = s.fresnel(VdotH);
        const float pdf = ggxVisibleNormalReflectionPdf(NdotV, h.z, alpha);
        // Each direction stands for Ωs = 1 / (n p) of the lobe (filtered importance sampling,
        // Křivánek & Colbert 2008) and reads the sky blurred over that much: the prefiltered
        // level of a GGX lobe of that extent (peak density 1 / (4π α'²): α' = √(Ωs / 4π)),
        // smooth where a box-filtered mip's 11° texels at n = 32 drew pinwheels on rough metals.
        const float omega = 1.0f / (float(samples) * std::max(pdf, 1e-20f));
        const float subAlpha = std::sqrt(omega / (4.0f * kPi));
        const glm::vec3 d = t * l.x + b * l.y + N * l.z;
        const glm::vec3 w = F * (g2 / G1v);
        sum += w * ibl.prefiltered(d, std::min(1.0f, std::sqrt(subAlpha)));
        weight += w;
    }
    // The lobe's mean radiance times its exact albedo from the DFG table: 32 samples estimate
    // the albedo within a few per cent, the mean radiance far better (a uniform sky gives it
    // exactly, so the white furnace stays exact).
    const glm::vec2 dfg = ibl.dfgAt(NdotV, s.roughness);
    const glm::vec3 albedo = s.lobeReflectance(dfg);
    return glm::vec3(weight.r > 0.0f ? sum.r / weight.r : 0.0f,
                     weight.g > 0.0f ? sum.g / weight.g : 0.0f,
                     weight.b > 0.0f ? sum.b / weight.b : 0.0f) *
           albedo;
}

IblShading shadeIbl(const Ibl& ibl, const PbrSurface& s, const glm::vec3& N, const glm::vec3& V,
                    IblSpecular method, float spread) {
    IblShading out;
    const float NdotV = std::max(glm::dot(N, V), 1e-4f);
    const glm::vec3 irradiance = ibl.irradiance(N);
    out.diffuse = diffuseAlbedo(s, NdotV) * irradiance * (1.0f / kPi);
    const glm::vec3 R = glm::reflect(-V, N);
    const glm::vec2 dfg = ibl.dfgAt(NdotV, s.roughness);
    const bool quadrature = method == IblSpecular::Quadrature ||
                            (method == IblSpecular::Auto && s.roughness >= kIblQuadratureRoughness);
    // The footprint widens the lobe the levels are read at, added in quadrature as two blurs
    // are (kFootprintAlpha, ibl.h).
    float lookup = s.roughness;
    if (spread > 0.0f) {
        const float a = s.roughness * s.roughness, af = kFootprintAlpha * spread;
        lookup = std::min(1.0f, std::sqrt(std::sqrt(a * a + af * af)));
    }
    const glm::vec3 single = quadrature && !ibl.levels.empty()
                                 ? specularQuadrature(ibl, s, N, V)
                                 : ibl.prefiltered(R, lookup) * s.lobeReflectance(dfg);
    // The multiple-scattering lobe, nearly diffuse, reflects the irradiance (as for every
    // other light; Turquin's 1 + F0 (1/y − 1) on the prefiltered value brightened coloured
    // rough metals past Cycles' multiscatter GGX).
    out.specular = single + multipleScatteringAlbedo(s, NdotV) * irradiance * (1.0f / kPi);
    return out;
}

float specularOcclusion(float NdotV, float ao, float roughness) {
    return std::clamp(std::pow(NdotV + ao, std::exp2(-16.0f * roughness - 1.0f)) - 1.0f + ao, 0.0f,
                      1.0f);
}

} // namespace dhdr
