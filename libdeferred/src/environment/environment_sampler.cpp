#include <algorithm>
#include <cmath>
#include <cstdint>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/environment/ibl.h>

namespace dhdr {

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
    // At most 256 wide, so that the tables stay in a core's L2 cache (at 512 wide the random
    // reads were a fifth of the shadow rays' time, and the noise is no lower: bench/README.md,
    // session 14). The texels' radiance is copied into the tables, the image not kept.
    EnvironmentImage env = full;
    while (env.width > 256)
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
    // The texel whose edges, the same rowCos and columnPhi that sample() draws between, hold
    // d: guessed from polynomial approximations of acos and atan2 (errors below 10⁻⁴ rad, a
    // texel is 0.025 rad wide) and moved to the neighbour the edges put d in. libm's acos and
    // atan2 were most of a lookup's arithmetic, and rounded differently from the edges.
    const float c = std::clamp(d.y, -1.0f, 1.0f);
    // Abramowitz & Stegun 4.4.45 for acos(|c|), mirrored for c < 0.
    const float a = std::abs(c);
    const float acosA =
        std::sqrt(1.0f - a) * (1.5707288f + a * (-0.2121144f + a * (0.0742610f + a * -0.0187293f)));
    const float theta = c < 0.0f ? kPi - acosA : acosA;
    int y = std::clamp(int(theta * (float(height) / kPi)), 0, height - 1);
    while (y > 0 && c > rowCos[size_t(y)])
        --y;
    while (y < height - 1 && !(c > rowCos[size_t(y) + 1]))
        ++y;
    // atan2(z, x) from atan of the octant's ratio in [0, 1] (an odd polynomial, 10⁻⁵ rad).
    const float ax = std::abs(d.x), az = std::abs(d.z);
    const float lo = std::min(ax, az), hi = std::max(ax, az);
    const float t = hi > 0.0f ? lo / hi : 0.0f, t2 = t * t;
    float phi =
        t *
        (0.99997726f +
         t2 * (-0.33262347f +
               t2 * (0.19354346f + t2 * (-0.11643287f + t2 * (0.05265332f + t2 * -0.01172120f)))));
    if (az > ax) phi = 0.5f * kPi - phi;
    if (d.x < 0.0f) phi = kPi - phi;
    if (d.z < 0.0f) phi = -phi;
    int x = int((0.5f + phi / (2.0f * kPi)) * float(width));
    x = (x % width + width) % width;
    // d lies at or after column x's left edge when (cos φ_x, sin φ_x) × (d.x, d.z) ≥ 0.
    auto after = [&](int column) {
        const glm::vec2 e = columnPhi[size_t(column)];
        return e.x * d.z - e.y * d.x >= 0.0f;
    };
    if (!after(x))
        x = (x + width - 1) % width;
    else if (after((x + 1) % width) && ax + az > 0.0f)
        x = (x + 1) % width;
    const Texel& texel = texels[size_t(y) * size_t(width) + size_t(x)];
    radiance = texel.radiance;
    return texel.pdf;
}

} // namespace dhdr
