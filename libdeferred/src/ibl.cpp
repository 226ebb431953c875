#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/ibl.h>
#include <dhdr/deferred/multiple_scattering.h>
#include <dhdr/deferred/sampling.h>

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

namespace {

// A GGX half vector about +Z for u in [0, 1)² (Walter et al. 2007, eq. 35–36).
glm::vec3 sampleGgxHalf(glm::vec2 u, float alpha) {
    const float a2 = alpha * alpha;
    const float cosTheta = std::sqrt((1.0f - u.x) / (1.0f + (a2 - 1.0f) * u.x));
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    const float phi = 2.0f * kPi * u.y;
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

// Prefilters one level: for each texel direction R (with N = V = R, the split sum's
// assumption), the GGX-weighted mean of the environment, Σ L(l) N·l / Σ N·l over importance
// samples, each read from the source mip whose texels match the sample's solid angle
// (Křivánek & Colbert 2008: lod = ½ log₂(Ωs / Ωp) + 1).
// The radiance along d of a chain of mips, level(0) … level(last), at a fractional level of
// detail (clamped to the chain): bilinear in each of the two nearest, linear between them.
template <class Level>
glm::vec3 trilinear(const Level& level, int last, const glm::vec3& d, float lod) {
    lod = std::clamp(lod, 0.0f, float(last));
    const int l0 = std::min(int(lod), last), l1 = std::min(l0 + 1, last);
    const glm::vec2 uv = equirectUV(d);
    const glm::vec3 a = level(l0).bilinear(uv);
    if (l1 == l0) return a;
    return glm::mix(a, level(l1).bilinear(uv), lod - float(l0));
}

EnvironmentImage prefilter(const std::vector<EnvironmentImage>& mips, int width, float roughness,
                           int samples, int nthreads) {
    EnvironmentImage out;
    out.width = width;
    out.height = width / 2;
    out.rgb.assign(size_t(out.width) * size_t(out.height) * 3, 0.0f);
    const float alpha = std::max(roughness * roughness, kMinAlpha);
    const double texelOmega = 4.0 * 3.14159265358979 / (double(mips[0].width) * mips[0].height);
    // The samples in the lobe's frame, the same for every texel.
    struct Sample {
        glm::vec3 l;
        float weight, lod;
    };
    std::vector<Sample> lobe;
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 h =
            sampleGgxHalf(hammersley(std::uint32_t(i), std::uint32_t(samples), 0), alpha);
        const glm::vec3 l = 2.0f * h.z * h - glm::vec3(0, 0, 1);
        if (l.z <= 0.0f) continue;
        // pdf(l) = D(h) (n·h) / (4 v·h) = D(h) / 4 with n = v.
        const float pdf = ggxDistribution(h.z, alpha) / 4.0f;
        const double omegaS = 1.0 / (double(samples) * std::max(pdf, 1e-20f));
        // Křivánek & Colbert 2008 add 1 to this lod against aliasing; measured on the eight
        // Poly Haven HDRIs against brute force (bench/prefilter_error.cpp) it over-blurs (+5 %
        // at level 1) and costs 0.7 points of error at every sample count, so it is left out.
        const float lod = std::max(0.0f, float(0.5 * std::log2(omegaS / texelOmega)));
        lobe.push_back({l, l.z, std::min(lod, float(mips.size() - 1))});
    }
    auto level = [&](int l) -> const EnvironmentImage& { return mips[size_t(l)]; };
    const int last = int(mips.size()) - 1;
    OIIO::parallel_for(
        0, out.height,
        [&](int64_t y) {
            for (int x = 0; x < out.width; ++x) {
                const glm::vec3 R = equirectDirection(
                    {(float(x) + 0.5f) / float(out.width), (float(y) + 0.5f) / float(out.height)});
                glm::vec3 t, b;
                orthonormalBasis(R, t, b);
                glm::dvec3 sum(0.0);
                double weight = 0.0;
                for (const Sample& s : lobe) {
                    const glm::vec3 d = t * s.l.x + b * s.l.y + R * s.l.z;
                    sum += glm::dvec3(trilinear(level, last, d, s.lod)) * double(s.weight);
                    weight += s.weight;
                }
                const glm::vec3 v(sum / std::max(weight, 1e-300));
                float* p = &out.rgb[3 * (size_t(y) * size_t(out.width) + size_t(x))];
                p[0] = v.r;
                p[1] = v.g;
                p[2] = v.b;
            }
        },
        perItem(nthreads));
    return out;
}

} // namespace

glm::vec2 integrateDFG(float NdotV, float roughness, int samples) {
    const float alpha = std::max(roughness * roughness, kMinAlpha);
    const glm::vec3 V(std::sqrt(std::max(0.0f, 1.0f - NdotV * NdotV)), 0.0f, NdotV);
    double x = 0.0, y = 0.0;
    for (int i = 0; i < samples; ++i) {
        const glm::vec3 H =
            sampleGgxHalf(hammersley(std::uint32_t(i), std::uint32_t(samples), 0), alpha);
        const float VdotH = glm::dot(V, H);
        const glm::vec3 L = 2.0f * VdotH * H - V;
        if (L.z <= 0.0f || VdotH <= 0.0f) continue;
        // f cos / pdf with pdf = D (n·h) / (4 v·h): Vis · 4 (v·h) (n·l) / (n·h), F left out.
        const double g =
            double(smithGgxCorrelatedVisibility(L.z, NdotV, alpha)) * 4.0 * VdotH * L.z / H.z;
        const double fc = std::pow(1.0 - VdotH, 5.0);
        x += g * fc;
        y += g;
    }
    return {float(x / samples), float(y / samples)};
}

namespace {

// Vose's alias table of n ≤ 65536 weights; `keep` in units of 2⁻¹⁶.
void buildAlias(const double* weights, int n, EnvironmentSampler::Bucket* buckets) {
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
        sum += weights[i];
    std::vector<double> scaled(static_cast<size_t>(n));
    std::vector<int> small, large;
    for (int i = 0; i < n; ++i) {
        scaled[size_t(i)] = sum > 0.0 ? weights[i] * n / sum : 1.0;
        (scaled[size_t(i)] < 1.0 ? small : large).push_back(i);
        buckets[i] = {0xffff, std::uint16_t(i)};
    }
    while (!small.empty() && !large.empty()) {
        const int s = small.back(), l = large.back();
        small.pop_back();
        // Rounded to 16 bits: a texel's probability moves by at most 2⁻¹⁷ / n, and the
        // density the sample reports is the rounded one's (test_ibl checks the histogram).
        buckets[s].keep = std::uint16_t(std::lround(scaled[size_t(s)] * 65535.0));
        buckets[s].alias = std::uint16_t(l);
        scaled[size_t(l)] -= 1.0 - scaled[size_t(s)];
        if (scaled[size_t(l)] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
}

// The bucket of an alias table for u in [0, 1): bucket ⌊u·n⌋, kept when `choice` (uniform in
// [0, 1)) is below its keep probability, else its alias.
int pickAlias(const EnvironmentSampler::Bucket* buckets, int n, float u, float choice) {
    const int i = std::min(int(u * float(n)), n - 1);
    return choice * 65535.0f < float(buckets[i].keep) ? i : buckets[i].alias;
}

} // namespace

void EnvironmentSampler::build(const EnvironmentImage& full) {
    // At most 512 wide: the texels' radiance is copied into the tables, the image not kept.
    EnvironmentImage env = full;
    while (env.width > 512)
        env = env.downsampled();
    width = env.width;
    height = env.height;
    const double pi = 3.14159265358979323846;
    rowCos.resize(size_t(height) + 1);
    for (int y = 0; y <= height; ++y)
        rowCos[size_t(y)] = float(std::cos(pi * y / height));
    columnPhi.resize(size_t(width));
    for (int x = 0; x < width; ++x) {
        const double phi = (double(x) / width - 0.5) * 2.0 * pi;
        columnPhi[size_t(x)] = {float(std::cos(phi)), float(std::sin(phi))};
    }
    // Weights in double: luminance times solid angle, summed in a fixed order.
    std::vector<double> weight(size_t(height) * size_t(width)), rowWeight(size_t(height), 0.0);
    total = 0.0;
    for (int y = 0; y < height; ++y) {
        const double omega = env.texelSolidAngle(y);
        for (int x = 0; x < width; ++x) {
            const glm::vec3 L = env.texel(x, y);
            const double w = std::max(0.0, 0.2126 * L.r + 0.7152 * L.g + 0.0722 * L.b) * omega;
            weight[size_t(y) * size_t(width) + size_t(x)] = w;
            rowWeight[size_t(y)] += w;
        }
        total += rowWeight[size_t(y)];
    }
    rows.assign(size_t(height), Bucket{});
    buckets.assign(size_t(height) * size_t(width), Bucket{});
    texels.assign(size_t(height) * size_t(width), Texel{});
    buildAlias(rowWeight.data(), height, rows.data());
    for (int y = 0; y < height; ++y)
        buildAlias(&weight[size_t(y) * size_t(width)], width, &buckets[size_t(y) * size_t(width)]);
    // The density each texel is actually drawn with, from the rounded tables: uniform in solid
    // angle within the texel, its probability over its solid angle.
    std::vector<double> rowP(size_t(height), 0.0), texelP(static_cast<size_t>(width));
    auto probabilities = [](const Bucket* b, int n, double* p) {
        std::fill(p, p + n, 0.0);
        for (int i = 0; i < n; ++i) {
            const double keep = b[i].keep / 65535.0;
            p[i] += keep / n;
            p[b[i].alias] += (1.0 - keep) / n;
        }
    };
    probabilities(rows.data(), height, rowP.data());
    for (int y = 0; y < height; ++y) {
        const size_t first = size_t(y) * size_t(width);
        probabilities(&buckets[first], width, texelP.data());
        const double omega = env.texelSolidAngle(y);
        for (int x = 0; x < width; ++x) {
            Texel& t = texels[first + size_t(x)];
            t.radiance = env.texel(x, y);
            t.pdf = total > 0.0 ? float(rowP[size_t(y)] * texelP[size_t(x)] / omega) : 0.0f;
        }
    }
}

glm::vec3 EnvironmentSampler::sample(glm::vec2 u, float& pdf, glm::vec3& radiance) const {
    // The row, then the texel within it, from the alias tables: the buckets from u, stratified
    // as the caller's sequence is. Which of a bucket's two texels, and where in the texel,
    // come from a hash of u: the digits of u below a bucket's width are the same for every
    // point of a stratified set (i / n and radical inverses step by whole buckets), so taking
    // them would make every sample of a pixel the same choice (a random-digit scramble, as
    // Owen scrambling gives pbrt-v4's samplers).
    std::uint64_t bits = (std::uint64_t(floatBits(u.x)) << 32) | floatBits(u.y);
    const std::uint64_t h0 = mixBits(bits), h1 = mixBits(bits ^ 0x9e3779b97f4a7c15ull);
    const float keepRow = unitFloat(h0), keepColumn = unitFloat(h0 << 24);
    const float fy = unitFloat(h1), fx = unitFloat(h1 << 24);
    const int y = pickAlias(rows.data(), height, u.y, keepRow);
    const size_t first = size_t(y) * size_t(width);
    const int x = pickAlias(&buckets[first], width, u.x, keepColumn);
    const float c0 = rowCos[size_t(y)], c1 = rowCos[size_t(y) + 1];
    const float cosTheta = c0 + fy * (c1 - c0);
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    // φ = φ_x + δ with δ < 2π / width ≤ 0.1: the angle-sum identities with δ's Taylor series
    // to δ⁵ (error below 2⁻³⁰) instead of a sine and cosine call.
    const float delta = fx * (2.0f * kPi / float(width)), d2 = delta * delta;
    const float cosDelta = 1.0f - d2 * (0.5f - d2 * (1.0f / 24.0f));
    const float sinDelta = delta * (1.0f - d2 * ((1.0f / 6.0f) - d2 * (1.0f / 120.0f)));
    const glm::vec2 edge = columnPhi[size_t(x)];
    const float cosPhi = edge.x * cosDelta - edge.y * sinDelta;
    const float sinPhi = edge.y * cosDelta + edge.x * sinDelta;
    const Texel& t = texels[first + size_t(x)];
    pdf = t.pdf;
    radiance = t.radiance;
    return {sinTheta * cosPhi, cosTheta, sinTheta * sinPhi};
}

float EnvironmentSampler::lookup(const glm::vec3& d, glm::vec3& radiance) const {
    const glm::vec2 uv = equirectUV(d);
    const int x = std::clamp(int(uv.x * float(width)), 0, width - 1);
    const int y = std::clamp(int(uv.y * float(height)), 0, height - 1);
    const Texel& t = texels[size_t(y) * size_t(width) + size_t(x)];
    radiance = t.radiance;
    return t.pdf;
}

glm::vec3 Ibl::irradiance(const glm::vec3& n) const {
    const std::array<float, 9> Y = shBasis(n);
    glm::vec3 e(0.0f);
    for (int i = 0; i < 9; ++i)
        e += sh[size_t(i)] * Y[size_t(i)];
    return glm::max(e, glm::vec3(0.0f));
}

glm::vec3 Ibl::prefiltered(const glm::vec3& R, float roughness) const {
    const int last = int(levels.size()) - 1;
    const float r = std::clamp(roughness, 0.0f, 1.0f);
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
    const float fx = std::clamp(NdotV, 0.0f, 1.0f) * float(n) - 0.5f;
    const float fy = std::clamp(roughness, 0.0f, 1.0f) * float(n) - 0.5f;
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
    ibl.levels.clear();
    ibl.levels.push_back(env);
    for (int k = 1; k < p.levels; ++k) {
        const int width = std::max(8, p.baseWidth >> (k - 1));
        ibl.levels.push_back(prefilter(mips, width, iblLevelRoughness(k, p.levels),
                                       iblLevelSamples(p, k), nthreads));
    }
    ibl.mips.assign(std::make_move_iterator(mips.begin() + 1), std::make_move_iterator(mips.end()));

    // (c) The DFG table.
    ibl.dfg.assign(size_t(p.dfgSize) * size_t(p.dfgSize), glm::vec2(0.0f));
    OIIO::parallel_for(
        0, p.dfgSize,
        [&](int64_t j) {
            for (int i = 0; i < p.dfgSize; ++i)
                ibl.dfg[size_t(j) * size_t(p.dfgSize) + size_t(i)] =
                    integrateDFG((float(i) + 0.5f) / float(p.dfgSize),
                                 (float(j) + 0.5f) / float(p.dfgSize), p.dfgSamples);
        },
        perItem(nthreads));
    return true;
}

glm::vec3 environmentAtLod(const Ibl& ibl, const glm::vec3& d, float lod) {
    auto level = [&](int l) -> const EnvironmentImage& {
        return l == 0 ? ibl.levels[0] : ibl.mips[size_t(l - 1)];
    };
    return trilinear(level, int(ibl.mips.size()), d, lod);
}

glm::vec3 specularQuadrature(const Ibl& ibl, const PbrSurface& s, const glm::vec3& N,
                             const glm::vec3& V, int samples) {
    const float NdotV = glm::dot(N, V);
    if (!(NdotV > 0.0f) || samples < 1) return glm::vec3(0.0f);
    const float alpha = s.alpha();
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    const glm::vec3 Vl(glm::dot(V, t), glm::dot(V, b), NdotV);
    const glm::vec3 F0 = s.F0();
    const EnvironmentImage& top = ibl.levels[0];
    const float texelOmega = 4.0f * kPi / (float(top.width) * float(top.height));
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
        const glm::vec3 F = schlickFresnel(F0, VdotH);
        const float pdf = ggxVisibleNormalReflectionPdf(NdotV, h.z, alpha);
        const float lod =
            0.5f * std::log2(1.0f / (float(samples) * std::max(pdf, 1e-20f) * texelOmega));
        const glm::vec3 d = t * l.x + b * l.y + N * l.z;
        const glm::vec3 w = F * (g2 / G1v);
        sum += w * environmentAtLod(ibl, d, lod);
        weight += w;
    }
    // The lobe's mean radiance times its exact albedo from the DFG table: 32 samples estimate
    // the albedo within a few per cent, the mean radiance far better (a uniform sky gives it
    // exactly, so the white furnace stays exact).
    const glm::vec2 dfg = ibl.dfgAt(NdotV, s.roughness);
    const glm::vec3 albedo = F0 * (dfg.y - dfg.x) + glm::vec3(dfg.x);
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
    const glm::vec3 F0 = s.F0();
    const bool quadrature = method == IblSpecular::Quadrature ||
                            (method == IblSpecular::Auto && s.roughness >= kIblQuadratureRoughness);
    // The footprint widens the lobe the levels are read at, added in quadrature as two blurs
    // are (kFootprintAlpha, ibl.h).
    float lookup = s.roughness;
    if (spread > 0.0f) {
        const float a = s.roughness * s.roughness, af = kFootprintAlpha * spread;
        lookup = std::min(1.0f, std::sqrt(std::sqrt(a * a + af * af)));
    }
    const glm::vec3 single =
        quadrature && !ibl.mips.empty()
            ? specularQuadrature(ibl, s, N, V)
            : ibl.prefiltered(R, lookup) * (F0 * (dfg.y - dfg.x) + glm::vec3(dfg.x));
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
