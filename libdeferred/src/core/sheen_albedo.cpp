// E_sheen(μ, roughness): the directional albedo of KHR_materials_sheen's lobe with colour 1,
// which its albedo scaling and the sheen's share of uniform light are made of. With the
// Neubelt visibility it passes 1 below μ ≈ 0.09 for roughnesses below 0.4 (2.2 at μ 1/64 and
// roughness 0.15): the scaling then leaves the base nothing, and the lobe gains energy.
#include <array>
#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/table_lookup.h>
#include <vector>

namespace dhdr {

namespace {

// 32 view angles (texel centres) × 32 roughnesses (0 to 1, both ends, each at least
// kMinSheenRoughness), a midpoint quadrature of 64 × 48 cells over the hemisphere of l (θ, and
// φ from v's azimuth, doubled by symmetry), summed in double: within 0.3 % of 256 × 192 cells
// from roughness 0.15 up (0.8 % at 0.07, grazing). sin(θh)^(1/α) = exp(log(sin²θh) / 2α): a
// cell's logarithm does not depend on the roughness, so it is taken once per view, and the
// exp is float's. 40-60 ms on this (loaded) 2-core machine, once per process, only when a
// sheen is shaded (128 × 128 cells with double's pow took 650 ms).
constexpr int kViews = 32, kRoughnesses = 32, kTheta = 64, kPhi = 48;

struct SheenTable {
    std::vector<float> albedo = std::vector<float>(size_t(kViews) * kRoughnesses); // [r][view]

    SheenTable() {
        constexpr double pi = 3.14159265358979323846;
        std::array<double, kPhi> cosPhi{};
        for (int b = 0; b < kPhi; ++b)
            cosPhi[size_t(b)] = std::cos((b + 0.5) / kPhi * pi);
        // The logarithms in float, for float's exp (a tenth of double's cost; the table is float).
        std::vector<float> logSin2(size_t(kTheta) * kPhi);
        std::vector<double> weight(size_t(kTheta) * kPhi);
        for (int i = 0; i < kViews; ++i) {
            const double mu = (i + 0.5) / kViews, sinV = std::sqrt(1.0 - mu * mu);
            for (int a = 0; a < kTheta; ++a) {
                const double theta = (a + 0.5) / kTheta * (pi / 2.0);
                const double cosL = std::cos(theta), sinL = std::sin(theta);
                // V cos θl and dω's sin θl.
                const double w = cosL * sinL / (4.0 * (cosL + mu - cosL * mu));
                for (int b = 0; b < kPhi; ++b) {
                    // |l + v|² = 2 (1 + l·v); N·H = (cos θl + μ) / |l + v|.
                    const double LdotV = cosL * mu + sinL * sinV * cosPhi[size_t(b)];
                    const double NdotH2 = (cosL + mu) * (cosL + mu) / (2.0 * (1.0 + LdotV));
                    const size_t c = size_t(a) * kPhi + size_t(b);
                    logSin2[c] = float(std::log(std::max(1.0 - NdotH2, 1e-30)));
                    weight[c] = w;
                }
            }
            for (int j = 0; j < kRoughnesses; ++j) {
                const double r =
                    std::max(double(j) / (kRoughnesses - 1), double(kMinSheenRoughness));
                const double invAlpha = 1.0 / (r * r);
                const float k = float(0.5 * invAlpha);
                double sum = 0.0;
                for (size_t c = 0; c < logSin2.size(); ++c)
                    sum += weight[c] * double(std::exp(k * logSin2[c]));
                // D's normalization; dω = sin θ dθ dφ over φ ∈ [0, 2π]: twice the half range.
                albedo[size_t(j) * kViews + size_t(i)] = float(
                    (2.0 + invAlpha) / (2.0 * pi) * 2.0 * sum * (pi / 2.0 / kTheta) * (pi / kPhi));
            }
        }
    }
};

// Linear interpolation between entries: at texel centres (views) or at both ends (roughness).
void cell(float v, int n, bool centred, int& i0, int& i1, float& a) {
    const float f =
        clampForTable(centred ? v * float(n) - 0.5f : v * float(n - 1), 0.0f, float(n - 1));
    i0 = int(f);
    i1 = std::min(i0 + 1, n - 1);
    a = f - float(i0);
}

} // namespace

float sheenAlbedo(float NdotV, float roughness) {
    static const SheenTable t; // thread-safe initialization (C++11)
    int i0, i1, j0, j1;
    float a, b;
    cell(NdotV, kViews, true, i0, i1, a);
    cell(std::max(roughness, kMinSheenRoughness), kRoughnesses, false, j0, j1, b);
    auto at = [&](int i, int j) { return t.albedo[size_t(j) * kViews + size_t(i)]; };
    return (at(i0, j0) * (1.0f - a) + at(i1, j0) * a) * (1.0f - b) +
           (at(i0, j1) * (1.0f - a) + at(i1, j1) * a) * b;
}

} // namespace dhdr
