// Sphere and rectangle lights against closed forms and numerical integration.
#include <cmath>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/lights/area.h>
#include <dhdr/deferred/lights/light.h>
#include <gtest/gtest.h>

using namespace dhdr;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// ∫ max(0, N·ω) dω over the cone of half-angle σ around `axis`, by a midpoint rule in
// (cos, φ) — the irradiance of a unit-radiance sphere, the horizon cut by the max.
double coneIrradiance(const glm::dvec3& N, const glm::dvec3& axis, double sinSigma) {
    const double cosSigma = std::sqrt(1.0 - sinSigma * sinSigma);
    const glm::dvec3 t = glm::normalize(std::abs(axis.x) < 0.9 ? glm::cross(axis, {1, 0, 0})
                                                               : glm::cross(axis, {0, 1, 0}));
    const glm::dvec3 b = glm::cross(axis, t);
    const int n = 2000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double c = 1.0 - (1.0 - cosSigma) * (i + 0.5) / n;
            const double s = std::sqrt(1.0 - c * c), phi = 2.0 * kPiD * (j + 0.5) / n;
            const glm::dvec3 w = c * axis + s * (std::cos(phi) * t + std::sin(phi) * b);
            sum += std::max(0.0, glm::dot(N, w));
        }
    return sum * 2.0 * kPiD * (1.0 - cosSigma) / (double(n) * n);
}

// Irradiance from a unit-radiance rectangle [−a, a] × [−b, b] in the plane z = h, at the origin,
// normal N, by a midpoint rule over the rectangle's area.
double rectangleIrradiance(const glm::dvec3& N, double a, double b, double h) {
    const int n = 1500;
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const glm::dvec3 p(-a + 2 * a * (i + 0.5) / n, -b + 2 * b * (j + 0.5) / n, h);
            const double d2 = glm::dot(p, p);
            const glm::dvec3 w = p / std::sqrt(d2);
            // dω = cos θ_light dA / d², the light facing −z.
            sum += std::max(0.0, glm::dot(N, w)) * w.z / d2;
        }
    return sum * (2 * a / n) * (2 * b / n);
}

} // namespace

TEST(AreaLights, SphereIrradianceMatchesNumericalIntegration) {
    const glm::vec3 N(0, 0, 1);
    // Elevations from straight above to partly and wholly below the horizon.
    for (double elevation : {90.0, 40.0, 12.0, 5.0, 0.0, -6.0, -20.0}) {
        const double e = elevation * kPiD / 180.0;
        const glm::dvec3 axis(std::cos(e), 0.0, std::sin(e));
        const double d = 2.0, radius = 0.5; // sin σ = 1/4, σ ≈ 14.5°
        const float E = sphereIrradiance(N, glm::vec3(axis * d), float(radius));
        const double reference = coneIrradiance(glm::dvec3(N), axis, radius / d);
        EXPECT_NEAR(E, reference, 2e-4 + 1e-3 * reference) << "elevation " << elevation;
    }
}

TEST(AreaLights, SphereLightOnAPlaneMatchesTheClosedForm) {
    // A sphere of radiance L wholly above the horizon gives E = π L (R/d)² cos β, which with
    // L = I / (π R²) is I cos β / d², as for a point light of the same intensity.
    Light sphere;
    sphere.type = LightType::Sphere;
    sphere.position = glm::vec3(0.3f, 2.0f, 0.0f);
    sphere.radius = 0.4f;
    sphere.intensity = 5.0f;
    PbrSurface white;
    white.baseColor = glm::vec3(1.0f);
    white.roughness = 1.0f;
    const glm::vec3 N(0, 1, 0), P(0, 0, 0);
    const glm::vec3 toCentre = sphere.position - P;
    const double d2 = glm::dot(toCentre, toCentre), cosBeta = toCentre.y / std::sqrt(d2);
    const double E = sphereIrradiance(N, toCentre, sphere.radius) * sphere.intensity /
                     (kPiD * sphere.radius * sphere.radius);
    EXPECT_NEAR(E, sphere.intensity * cosBeta / d2, 1e-5);
}

TEST(AreaLights, RectangleIrradianceMatchesClosedFormAndIntegration) {
    // Parallel rectangle 2a × 2b at height h, centred over the point:
    // E / L = 2 [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))], X = a/h, Y = b/h.
    const double a = 0.5, b = 0.25, h = 0.8, X = a / h, Y = b / h;
    const double closed = 2.0 * (X / std::sqrt(1 + X * X) * std::atan(Y / std::sqrt(1 + X * X)) +
                                 Y / std::sqrt(1 + Y * Y) * std::atan(X / std::sqrt(1 + Y * Y)));
    const glm::vec3 corners[4] = {{-a, -b, h}, {a, -b, h}, {a, b, h}, {-a, b, h}};
    EXPECT_NEAR(polygonIrradiance({0, 0, 1}, corners, 4), closed, 1e-5);
    EXPECT_NEAR(rectangleIrradiance({0, 0, 1}, a, b, h), closed, 1e-4);
    // Tilted so that the horizon cuts the rectangle: against the area integral.
    for (double tilt : {30.0, 60.0, 80.0}) {
        const double t = tilt * kPiD / 180.0;
        const glm::dvec3 N(std::sin(t), 0.0, std::cos(t));
        EXPECT_NEAR(polygonIrradiance(glm::vec3(N), corners, 4), rectangleIrradiance(N, a, b, h),
                    2e-4)
            << "tilt " << tilt;
    }
}

TEST(AreaLights, RectangleFacingAwayContributesZero) {
    Light rect;
    rect.type = LightType::Rectangle;
    rect.position = glm::vec3(0, 1, 0);
    rect.direction = glm::vec3(0, 1, 0); // emits upwards, away from the floor below
    rect.up = glm::vec3(0, 0, 1);
    rect.width = rect.height = 0.5f;
    rect.intensity = 100.0f;
    PbrSurface s;
    const glm::vec3 N(0, 1, 0), V = glm::normalize(glm::vec3(0.2f, 1.0f, 0.3f));
    EXPECT_EQ(shadeLight(rect, s, glm::vec3(0.1f, 0.0f, 0.2f), N, V), glm::vec3(0.0f));
    rect.direction = glm::vec3(0, -1, 0);
    EXPECT_GT(shadeLight(rect, s, glm::vec3(0.1f, 0.0f, 0.2f), N, V).g, 0.0f);
}

TEST(AreaLights, SmallAreaLightsTendToThePointLight) {
    Light point;
    point.position = glm::vec3(0.2f, 1.5f, -0.3f);
    point.intensity = 3.0f;
    point.range = 10.0f;
    Light sphere = point;
    sphere.type = LightType::Sphere;
    sphere.radius = 1e-3f;
    Light rect = point;
    rect.type = LightType::Rectangle;
    rect.direction = glm::vec3(0, -1, 0);
    rect.up = glm::vec3(0, 0, 1);
    rect.width = rect.height = 1e-3f;
    PbrSurface s;
    s.baseColor = glm::vec3(0.6f);
    s.roughness = 0.5f;
    const glm::vec3 P(0, 0, 0), N(0, 1, 0), V = glm::normalize(glm::vec3(-0.5f, 1.0f, 0.4f));
    const glm::vec3 ref = shadeLight(point, s, P, N, V);
    // The rectangle is a Lambertian emitter: I cos θ towards P.
    const float cosLight = glm::normalize(point.position - P).y;
    EXPECT_NEAR(shadeLight(sphere, s, P, N, V).g, ref.g, 1e-3 * ref.g);
    EXPECT_NEAR(shadeLight(rect, s, P, N, V).g, ref.g * cosLight, 1e-3 * ref.g);
}

TEST(AreaLights, SpecularNormalizationKeepsTheHighlightsEnergy) {
    // Total specular radiance over a floor under a light, sphere of radius 0.3 against a
    // point: without normalization the widened highlight would carry (α′/α)² ≈ 9 times more.
    auto total = [](const Light& light) {
        PbrSurface s;
        s.baseColor = glm::vec3(1.0f);
        s.metallic = 1.0f;
        s.roughness = 0.3f;
        const glm::vec3 eye(0.0f, 2.0f, 3.0f), N(0, 1, 0);
        double sum = 0.0;
        for (int i = 0; i < 400; ++i)
            for (int j = 0; j < 400; ++j) {
                const glm::vec3 P(-4.0f + 8.0f * (i + 0.5f) / 400, 0.0f,
                                  -4.0f + 8.0f * (j + 0.5f) / 400);
                sum += shadeLight(light, s, P, N, glm::normalize(eye - P)).g;
            }
        return sum;
    };
    Light point;
    point.position = glm::vec3(0.0f, 1.0f, -1.0f);
    Light sphere = point;
    sphere.type = LightType::Sphere;
    sphere.radius = 0.3f;
    const double ratio = total(sphere) / total(point);
    EXPECT_GT(ratio, 0.8);
    EXPECT_LT(ratio, 1.25);
}

// A sun with an angle against Monte Carlo over its disk in double (directions uniform in the
// cone, each with radiance E / Ω): summed over views around the mirror direction, where the
// representative point puts the highlight, the disk's light agrees within 15 % for rough and
// glossy surfaces (Karis's normalization measured: 0.86–1.01 at 10°; a point sun is 8.8× too
// bright there at roughness 0.15); and as the angle goes to 0 it becomes the point sun's.
TEST(SunDisk, RepresentativePointAgainstIntegrationOverTheDisk) {
    const glm::vec3 N(0.0f, 0.0f, 1.0f);
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(-0.5f, 0.0f, -1.0f));
    sun.intensity = 3.0f;
    const glm::vec3 L = -sun.direction;
    for (const float roughness : {0.15f, 0.3f, 0.6f}) {
        PbrSurface s;
        s.baseColor = glm::vec3(0.8f, 0.6f, 0.3f);
        s.metallic = 1.0f;
        s.roughness = roughness;
        sun.angle = 10.0f * kPi / 180.0f;
        const float cosMax = std::cos(0.5f * sun.angle);
        glm::vec3 t, b;
        orthonormalBasis(L, t, b);
        double approx = 0.0, exact = 0.0;
        for (int i = -6; i <= 6; ++i)
            for (int j = -6; j <= 6; ++j) {
                // Views around the mirror direction of the sun's centre.
                const glm::vec3 V =
                    glm::normalize(glm::vec3(-L.x + 0.03f * float(i), 0.03f * float(j), L.z));
                approx += shadePunctual(sun, s, glm::vec3(0.0f), N, V).g;
                double sum = 0.0;
                constexpr int kSamples = 4096;
                for (int k = 0; k < kSamples; ++k) {
                    const glm::vec3 c =
                        uniformCone(hammersley(std::uint32_t(k), kSamples, 7), cosMax);
                    const glm::vec3 l = glm::normalize(c.x * t + c.y * b + c.z * L);
                    const float cosTheta = glm::dot(N, l);
                    if (cosTheta <= 0.0f) continue;
                    sum += double(evaluateBrdf(s, N, V, l).g) * cosTheta;
                }
                exact += sum / kSamples * double(sun.intensity);
            }
        EXPECT_NEAR(approx / exact, 1.0, 0.15) << "roughness " << roughness;
        // A vanishing disk is the point sun.
        sun.angle = 1e-5f;
        const glm::vec3 V = glm::normalize(glm::vec3(0.3f, 0.1f, 1.0f));
        Light point = sun;
        point.angle = 0.0f;
        const glm::vec3 a = shadeLight(sun, s, {}, N, V), p = shadeLight(point, s, {}, N, V);
        EXPECT_NEAR(a.g / p.g, 1.0f, 1e-3f) << "roughness " << roughness;
    }
}
