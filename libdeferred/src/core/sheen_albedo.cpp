// E_sheen(μ, roughness): the directional albedo of KHR_materials_sheen's lobe with colour 1,
// which its albedo scaling and the sheen's share of uniform light are made of.
#include <array>
#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/table_lookup.h>
#include <vector>

namespace dhdr {

namespace {

// 32 view angles (texel centres) × 32 roughnesses (0 to 1, both ends, each at least
// kMinSheenRoughness), a midpoint quadrature of 128 × 128 cells over the hemisphere of l (θ,
// and φ from v's azimuth, doubled by symmetry) in double.
constexpr int kViews = 32, kRoughnesses = 32, kTheta = 128, kPhi = 128;

struct SheenTable {
    std::vector<float> albedo = std::vector<float>(size_t(kViews) * kRoughnesses); // [r][view]

    SheenTable() {
        constexpr double pi = 3.14159265358979323846;
        std::array<double, kPhi> cosPhi{};
        for (int b = 0; b < kPhi; ++b)
            cosPhi[size_t(b)] = std::cos((b + 0.5) / kPhi * pi);
        for (int j = 0; j < kRoughnesses; ++j) {
            const double r = std::max(double(j) / (kRoughnesses - 1), double(kMinSheenRoughness));
            const double invAlpha = 1.0 / (r * r);
            for (int i = 0; i < kViews; ++i) {
                const double mu = (i + 0.5) / kViews, sinV = std::sqrt(1.0 - mu * mu);
                double sum = 0.0;
                for (int a = 0; a < kTheta; ++a) {
                    const double theta = (a + 0.5) / kTheta * (pi / 2.0);
                    const double cosL = std::cos(theta), sinL = std::sin(theta);
                    const double vis = 1.0 / (4.0 * (cosL + mu - cosL * mu));
                    for (int b = 0; b < kPhi; ++b) {
                        // |l + v|² = 2 (1 + l·v); N·H = (cos θl + μ) / |l + v|.
                        const double LdotV = cosL * mu + sinL * sinV * cosPhi[size_t(b)];
                        const double NdotH2 = (cosL + mu) * (cosL + mu) / (2.0 * (1.0 + LdotV));
                        const double sin2 = std::max(0.0, 1.0 - NdotH2);
                        const double D =
                            (2.0 + invAlpha) * std::pow(sin2, 0.5 * invAlpha) / (2.0 * pi);
                        sum += D * vis * cosL * sinL;
                    }
                }
                // dω = sin θ dθ dφ over φ ∈ [0, 2π]: twice the half range.
                albedo[size_t(j) * kViews + size_t(i)] =
                    float(2.0 * sum * (pi / 2.0 / kTheta) * (pi / kPhi));
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
