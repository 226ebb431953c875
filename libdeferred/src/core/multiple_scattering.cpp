#include <algorithm>
#include <array>
#include <cmath>
#include <dhdr/deferred/core/brdf_integrals.h>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/table_lookup.h>
#include <vector>

namespace dhdr {

namespace {

// E(μ, roughness) at 64 view angles (texel centres) × 32 roughnesses (0 to 1, both ends
// included), 1024 GGX samples each (integrateDFG, ≈ 0.1 % of the albedo): about 30 ms, once
// per process.
constexpr int kViews = 64, kRoughnesses = 32, kSamples = 1024;

struct AlbedoTable {
    std::vector<glm::vec2> terms; // [roughness][view]
    std::array<float, kRoughnesses> average{};

    AlbedoTable() : terms(size_t(kViews) * kRoughnesses) {
        for (int j = 0; j < kRoughnesses; ++j) {
            const float roughness = float(j) / float(kRoughnesses - 1);
            double sum = 0.0;
            for (int i = 0; i < kViews; ++i) {
                const float mu = (float(i) + 0.5f) / float(kViews);
                const glm::vec2 t = integrateDFG(mu, roughness, kSamples);
                terms[size_t(j) * kViews + size_t(i)] = t;
                sum += double(t.y) * mu; // midpoint rule for 2 ∫ E μ dμ
            }
            average[size_t(j)] = float(2.0 * sum / kViews);
        }
    }
};

const AlbedoTable& table() {
    static const AlbedoTable t; // thread-safe initialization (C++11)
    return t;
}

// Linear interpolation between entries: at texel centres (views) or at both ends (roughness).
void cell(float v, int n, bool centred, int& i0, int& i1, float& a) {
    const float f =
        clampForTable(centred ? v * float(n) - 0.5f : v * float(n - 1), 0.0f, float(n - 1));
    i0 = int(f);
    i1 = std::min(i0 + 1, n - 1);
    a = f - float(i0);
}

struct MsFactors {
    float oneMinusEo, norm; // 1 − E(μo); 1 / (π (1 − E_avg)), 0 where nothing is lost
    glm::vec3 fresnel;      // F_avg² E_avg / (1 − F_avg (1 − E_avg))
};

MsFactors factors(const PbrSurface& s, float NdotV) {
    MsFactors m{};
    const float Eavg = ggxAverageAlbedo(s.roughness);
    const float lost = 1.0f - Eavg;
    if (!(lost > 1e-4f)) return m; // a smooth lobe loses nothing
    m.oneMinusEo = std::max(0.0f, 1.0f - ggxAlbedoTerms(NdotV, s.roughness).y);
    m.norm = 1.0f / (kPi * lost);
    const glm::vec3 F0 = s.F0();
    const glm::vec3 Favg = F0 + (glm::vec3(s.f90()) - F0) * (1.0f / 21.0f);
    m.fresnel = Favg * Favg * Eavg / (glm::vec3(1.0f) - Favg * lost);
    return m;
}

// cos φ at the midpoints of n steps over [0, π] (the tables' azimuths, doubled by symmetry).
template <int n>
std::array<double, n> cosines() {
    std::array<double, n> c{};
    for (int b = 0; b < n; ++b)
        c[size_t(b)] = std::cos((b + 0.5) / n * 3.14159265358979323846);
    return c;
}

// T(μ) at kViews view angles (texel centres): a midpoint quadrature of 256 × 256 cells over
// the hemisphere of l (θ, and φ from v's azimuth by symmetry), in double.
struct DiffuseTable {
    std::array<float, kViews> transmission{};

    DiffuseTable() {
        constexpr int kTheta = 256, kPhi = 256;
        constexpr double pi = 3.14159265358979323846;
        // cos φ once per column and x⁵ by products: the same floats as cos and pow in the loop
        // (checked), 7 ms instead of 104 at every start.
        const std::array<double, kPhi> cosPhi = cosines<kPhi>();
        for (int i = 0; i < kViews; ++i) {
            const double mu = (i + 0.5) / kViews, sinV = std::sqrt(1.0 - mu * mu);
            double sum = 0.0;
            for (int a = 0; a < kTheta; ++a) {
                const double theta = (a + 0.5) / kTheta * (pi / 2.0);
                const double cosL = std::cos(theta), sinL = std::sin(theta);
                for (int b = 0; b < kPhi; ++b) {
                    const double LdotV = cosL * mu + sinL * sinV * cosPhi[size_t(b)];
                    const double x = 1.0 - std::sqrt(std::max(0.0, 0.5 * (1.0 + LdotV))),
                                 x2 = x * x;
                    sum += (1.0 - x2 * x2 * x) * cosL * sinL;
                }
            }
            // dω = sin θ dθ dφ over φ ∈ [0, 2π]: twice the half range.
            transmission[size_t(i)] = float(2.0 * sum * (pi / 2.0 / kTheta) * (pi / kPhi) / pi);
        }
    }
};

// B(μ, roughness) at kViews view angles (texel centres) × kRoughnesses: the same midpoint
// quadrature as T(μ), of Burley's bracket (DiffuseModel::Burley) times cos θ / π.
struct BurleyTable {
    std::vector<float> albedo = std::vector<float>(size_t(kViews) * kRoughnesses); // [r][view]

    BurleyTable() {
        constexpr int kTheta = 128, kPhi = 128;
        constexpr double pi = 3.14159265358979323846;
        const std::array<double, kPhi> cosPhi = cosines<kPhi>();
        for (int j = 0; j < kRoughnesses; ++j) {
            const double roughness = double(j) / (kRoughnesses - 1);
            for (int i = 0; i < kViews; ++i) {
                const double mu = (i + 0.5) / kViews, sinV = std::sqrt(1.0 - mu * mu);
                const double FV = std::pow(1.0 - mu, 5.0);
                double sum = 0.0;
                for (int a = 0; a < kTheta; ++a) {
                    const double theta = (a + 0.5) / kTheta * (pi / 2.0);
                    const double cosL = std::cos(theta), sinL = std::sin(theta);
                    const double FL = std::pow(1.0 - cosL, 5.0);
                    for (int b = 0; b < kPhi; ++b) {
                        const double RR =
                            roughness * (cosL * mu + sinL * sinV * cosPhi[size_t(b)] + 1.0);
                        const double f = (1.0 - 0.5 * FL) * (1.0 - 0.5 * FV) +
                                         RR * (FL + FV + FL * FV * (RR - 1.0));
                        sum += f * cosL * sinL;
                    }
                }
                albedo[size_t(j) * kViews + size_t(i)] =
                    float(2.0 * sum * (pi / 2.0 / kTheta) * (pi / kPhi) / pi);
            }
        }
    }
};

} // namespace

float burleyDiffuseAlbedo(float NdotV, float roughness) {
    static const BurleyTable t;
    int i0, i1, j0, j1;
    float a, b;
    cell(NdotV, kViews, true, i0, i1, a);
    cell(roughness, kRoughnesses, false, j0, j1, b);
    auto at = [&](int i, int j) { return t.albedo[size_t(j) * kViews + size_t(i)]; };
    return (at(i0, j0) * (1.0f - a) + at(i1, j0) * a) * (1.0f - b) +
           (at(i0, j1) * (1.0f - a) + at(i1, j1) * a) * b;
}

float diffuseFresnelTransmission(float NdotV) {
    static const DiffuseTable t;
    int i0, i1;
    float a;
    cell(NdotV, kViews, true, i0, i1, a);
    return t.transmission[size_t(i0)] * (1.0f - a) + t.transmission[size_t(i1)] * a;
}

glm::vec2 ggxAlbedoTerms(float NdotV, float roughness) {
    const AlbedoTable& t = table();
    int i0, i1, j0, j1;
    float a, b;
    cell(NdotV, kViews, true, i0, i1, a);
    cell(roughness, kRoughnesses, false, j0, j1, b);
    auto at = [&](int i, int j) { return t.terms[size_t(j) * kViews + size_t(i)]; };
    return glm::mix(glm::mix(at(i0, j0), at(i1, j0), a), glm::mix(at(i0, j1), at(i1, j1), a), b);
}

float ggxAverageAlbedo(float roughness) {
    const AlbedoTable& t = table();
    int j0, j1;
    float b;
    cell(roughness, kRoughnesses, false, j0, j1, b);
    return t.average[size_t(j0)] + (t.average[size_t(j1)] - t.average[size_t(j0)]) * b;
}

glm::vec3 multipleScatteringBrdf(const PbrSurface& s, float NdotV, float NdotL) {
    const MsFactors m = factors(s, NdotV);
    if (m.norm == 0.0f) return glm::vec3(0.0f);
    const float oneMinusEi = std::max(0.0f, 1.0f - ggxAlbedoTerms(NdotL, s.roughness).y);
    return m.fresnel * (m.oneMinusEo * oneMinusEi * m.norm);
}

glm::vec3 multipleScatteringAlbedo(const PbrSurface& s, float NdotV) {
    const MsFactors m = factors(s, NdotV);
    return m.norm == 0.0f ? glm::vec3(0.0f) : m.fresnel * m.oneMinusEo;
}

} // namespace dhdr
