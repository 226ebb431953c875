// The multiple-scattering lobe (multiple_scattering.h) against closed forms: energy
// conservation of a white metal, and one material under every light.
#include "scene_builder.h"

#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/gbuffer/shading_point.h>
#include <dhdr/deferred/lights/light.h>
#include <gtest/gtest.h>

using namespace dhdr;

namespace {

// ∫ f(l, v) cos θ_l dω over the hemisphere by the midpoint rule in (cos θ, φ), where
// dω = d(cos θ) dφ: 1024 × 1024 points, in double. `singleOnly` leaves the
// multiple-scattering lobe out.
glm::dvec3 albedo(const PbrSurface& s, float NdotV, bool singleOnly = false) {
    const glm::vec3 N(0.0f, 0.0f, 1.0f);
    const glm::vec3 V(std::sqrt(1.0f - NdotV * NdotV), 0.0f, NdotV);
    constexpr int n = 1024;
    const double pi = 3.14159265358979323846;
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i) {
        const double mu = (i + 0.5) / n;
        const double sinTheta = std::sqrt(1.0 - mu * mu);
        for (int j = 0; j < n; ++j) {
            const double phi = 2.0 * pi * (j + 0.5) / n;
            const glm::vec3 L(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)),
                              float(mu));
            glm::vec3 f = evaluateBrdf(s, N, V, L);
            if (singleOnly) f -= multipleScatteringBrdf(s, NdotV, L.z);
            sum += glm::dvec3(f) * mu;
        }
    }
    return sum * (2.0 * pi / (double(n) * n));
}

PbrSurface metal(glm::vec3 colour, float roughness) {
    PbrSurface s;
    s.baseColor = colour;
    s.metallic = 1.0f;
    s.roughness = roughness;
    return s;
}

} // namespace

// A white metal (F = 1) loses no light: ∫ (f + f_ms) cos dω = 1 at every view angle and
// roughness (Kulla & Conty's construction). Without the lobe a rough one reflects 50-90 %.
TEST(MultipleScattering, WhiteMetalReflectsAllTheLight) {
    for (float roughness : {0.4f, 0.7f, 1.0f})
        for (float mu : {0.2f, 0.5f, 1.0f}) {
            const PbrSurface s = metal(glm::vec3(1.0f), roughness);
            const double a = albedo(s, mu).g;
            EXPECT_NEAR(a, 1.0, 0.012) << "roughness " << roughness << ", N·V " << mu;
            if (roughness == 1.0f) {
                EXPECT_LT(albedo(s, mu, true).g, 0.9);
            }
        }
}

// The table's average albedo is the cosine-weighted mean of the integral above.
TEST(MultipleScattering, AverageAlbedoIsTheMeanOverViews) {
    const PbrSurface s = metal(glm::vec3(1.0f), 0.8f);
    double sum = 0.0;
    constexpr int n = 16;
    for (int i = 0; i < n; ++i) {
        const float mu = (float(i) + 0.5f) / float(n);
        sum += albedo(s, mu, true).g * mu;
    }
    EXPECT_NEAR(2.0 * sum / n, ggxAverageAlbedo(0.8f), 0.01);
}

// One material under every light: a rough gold, a rough dielectric's specular layer and a
// coloured dielectric with its diffuse layer under radiance 1 from every direction reflect the
// same light whether it comes as many directional lights (the quadrature of evaluateBrdf), as
// an ambient light or as a baked environment. (The diffuse layer under an environment was
// c_diff E / π, 3-5 % above what the Fresnel mix of evaluateBrdf leaves it; the reference
// path tracer found it, test_path_tracer.)
TEST(MultipleScattering, OneMaterialUnderEveryLight) {
    const Light sky = dhdr::test::uniformSky();
    Light ambient;
    ambient.type = LightType::Ambient;
    const glm::vec3 N(0.0f, 0.0f, 1.0f);
    for (float roughness : {0.5f, 0.9f})
        for (float mu : {0.3f, 0.8f}) {
            const glm::vec3 V(std::sqrt(1.0f - mu * mu), 0.0f, mu);
            PbrSurface dielectric;
            dielectric.baseColor = glm::vec3(0.0f); // its specular layer alone
            dielectric.roughness = roughness;
            PbrSurface coloured;
            coloured.baseColor = glm::vec3(0.8f, 0.5f, 0.2f);
            coloured.roughness = roughness;
            PbrSurface burley = coloured;
            burley.diffuse = DiffuseModel::Burley;
            // KHR_materials_sheen over it: the sheen's share of uniform light (shadeEnvironment,
            // the ambient light's layering) against the layered BRDF integrated.
            PbrSurface sheened = coloured;
            sheened.sheen = {glm::vec3(0.9f, 0.6f, 0.3f), 0.5f};
            for (const PbrSurface& s : {metal(glm::vec3(1.0f, 0.78f, 0.34f), roughness), dielectric,
                                        coloured, burley, sheened}) {
                const glm::dvec3 exact = albedo(s, mu);
                const glm::vec3 underSky = shadeLight(sky, s, glm::vec3(0.0f), N, V);
                const glm::vec3 underAmbient = shadeLight(ambient, s, glm::vec3(0.0f), N, V);
                for (int c = 0; c < 3; ++c) {
                    const double tolerance = 0.015 * exact[c] + 2e-3;
                    EXPECT_NEAR(underSky[c], exact[c], tolerance)
                        << "environment, roughness " << roughness << ", N·V " << mu;
                    EXPECT_NEAR(underAmbient[c], exact[c], tolerance)
                        << "ambient, roughness " << roughness << ", N·V " << mu;
                }
            }
        }
}

// Burley's diffuse (Blender's Principled BSDF) against its closed forms: seen head-on its
// albedo is 1 − ∫₀¹ (1−c)⁵ c dc = 41/42 at roughness 0 (the (1 − ½F_L) factor), and adds
// 2 ∫₀¹ (1+c)(1−c)⁵ c dc = 1/14 of retro-reflection at roughness 1: 87/84. The table between
// against the quadrature of diffuseBrdf in double, and 1.1–1.5× Lambert at roughness 1.
TEST(Diffuse, BurleyAlbedoAgainstItsClosedFormsAndItsFormula) {
    EXPECT_NEAR(burleyDiffuseAlbedo(1.0f, 0.0f), 41.0 / 42.0, 1e-3);
    EXPECT_NEAR(burleyDiffuseAlbedo(1.0f, 1.0f), 87.0 / 84.0, 1e-3);
    PbrSurface white;
    white.baseColor = glm::vec3(1.0f);
    white.diffuse = DiffuseModel::Burley;
    const glm::vec3 N(0.0f, 0.0f, 1.0f);
    for (float roughness : {0.0f, 0.37f, 1.0f})
        for (float mu : {0.1f, 0.5f, 0.95f}) {
            white.roughness = roughness;
            const glm::vec3 V(std::sqrt(1.0f - mu * mu), 0.0f, mu);
            constexpr int n = 512;
            double sum = 0.0;
            for (int i = 0; i < n; ++i) {
                const double c = (i + 0.5) / n, sinTheta = std::sqrt(1.0 - c * c);
                for (int j = 0; j < n; ++j) {
                    const double phi = 2.0 * 3.14159265358979323846 * (j + 0.5) / n;
                    const glm::vec3 L(float(sinTheta * std::cos(phi)),
                                      float(sinTheta * std::sin(phi)), float(c));
                    sum += double(diffuseBrdf(white, N, V, L, glm::vec3(0.0f)).r) * c;
                }
            }
            const double exact = sum * 2.0 * 3.14159265358979323846 / (double(n) * n);
            EXPECT_NEAR(burleyDiffuseAlbedo(mu, roughness), exact, 2e-3 * exact)
                << "roughness " << roughness << ", N·V " << mu;
            if (roughness == 1.0f) {
                EXPECT_GT(exact, 1.0);
                EXPECT_LT(exact, 1.6);
            }
        }
}

// --diffuse burley in the frame: a rough floor under a sun, lit by the G-buffer pass with each
// model. Per pixel, the difference is exactly the two diffuse layers' (the specular layer is
// the same): c/π E cos θ_l [Burley's bracket − (1 − F(v·h))], written out here from the
// formula.
TEST(Diffuse, TheFramesDiffuseLayerIsBurleysFormula) {
    using namespace dhdr::test;
    Scene scene = emptyScene();
    addFloor(scene, 3.0f);
    scene.materials[0].baseColor = glm::vec3(0.7f, 0.6f, 0.5f);
    scene.materials[0].roughness = 0.8f;
    const Camera camera = Camera::lookAt({0.0, 2.0, 3.0}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(scene, camera, 32, 32);
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.4f, -1.0f, -0.3f));
    sun.intensity = 2.0f;
    LightingParams p;
    const ImageBuf lambert = shade(gbuf, {sun}, nullptr, p);
    p.diffuse = DiffuseModel::Burley;
    const ImageBuf burley = shade(gbuf, {sun}, nullptr, p);
    GBufferPixels g;
    ImageBuf errors;
    ASSERT_TRUE(openGBuffer(gbuf, g, errors));
    const GBufferView view(*g.pixels, g.layout, g.camera);
    int checked = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            if (view.samples(x, y) == 0) continue;
            const ShadingPoint sp = view.at(x, y);
            const glm::dvec3 N(sp.N), V(sp.V), L(-sun.direction);
            const double cl = glm::dot(N, L), cv = glm::dot(N, V);
            const double FL = std::pow(1.0 - cl, 5.0), FV = std::pow(1.0 - cv, 5.0);
            const double RR = sp.surface.roughness * (glm::dot(L, V) + 1.0);
            const double bracket =
                (1.0 - 0.5 * FL) * (1.0 - 0.5 * FV) + RR * (FL + FV + FL * FV * (RR - 1.0));
            const double VdotH = glm::dot(V, glm::normalize(L + V));
            const double F = 0.04 + 0.96 * std::pow(1.0 - VdotH, 5.0);
            for (int c = 0; c < 3; ++c) {
                const double expected = sp.surface.baseColor[c] / 3.14159265358979323846 *
                                        sun.intensity * cl * (bracket - (1.0 - F));
                EXPECT_NEAR(px(burley, x, y)[c] - px(lambert, x, y)[c], expected,
                            1e-4 + 1e-3 * std::abs(expected))
                    << x << "," << y;
            }
            ++checked;
        }
    EXPECT_GT(checked, 300);
}

// Directions drawn by GGX's visible normals (sampling.h) with their density give an unbiased
// estimate of the single-scattering lobe's albedo: the mean of D · Vis · cos / pdf over 4096
// stratified samples equals the quadrature.
TEST(Sampling, GgxVisibleNormalsIntegrateTheLobe) {
    for (float roughness : {0.3f, 0.6f, 1.0f})
        for (float mu : {0.25f, 0.9f}) {
            const PbrSurface s = metal(glm::vec3(1.0f), roughness);
            const float alpha = s.alpha();
            const glm::vec3 V(std::sqrt(1.0f - mu * mu), 0.0f, mu);
            constexpr int n = 4096;
            double sum = 0.0;
            for (int i = 0; i < n; ++i) {
                const glm::vec3 H =
                    sampleGgxVisibleNormal(V, alpha, hammersley(std::uint32_t(i), n, 3));
                const glm::vec3 L = 2.0f * glm::dot(V, H) * H - V;
                if (L.z <= 0.0f) continue; // reflected below the surface: the lobe's loss
                const float pdf = ggxVisibleNormalReflectionPdf(mu, H.z, alpha);
                sum += double(ggxDistribution(H.z, alpha) *
                              smithGgxCorrelatedVisibility(L.z, mu, alpha) * L.z / pdf);
            }
            EXPECT_NEAR(sum / n, albedo(s, mu, true).g, 0.01)
                << "roughness " << roughness << ", N·V " << mu;
        }
}

// Every table lookup takes NaN and ±Inf (issue 48: a G-buffer normal that could not be
// normalised gave ggxAlbedoTerms a NaN cosine, which indexed its table at INT_MIN): an end of
// the table, finite.
TEST(TableLookups, NonFiniteArgumentsReadAnEndOfTheTable) {
    EnvironmentImage level;
    level.width = 4;
    level.height = 2;
    level.rgb.assign(24, 0.5f);
    Ibl ibl;
    ibl.params.dfgSize = 4;
    ibl.dfg.assign(16, glm::vec2(0.25f, 0.75f));
    ibl.levels = {level, level};
    const float odd[] = {NAN, INFINITY, -INFINITY, 1e30f, -1e30f};
    for (const float v : odd) {
        SCOPED_TRACE(v);
        for (const float r : {0.5f, v}) {
            const glm::vec2 e = ggxAlbedoTerms(v, r);
            EXPECT_TRUE(std::isfinite(e.x) && std::isfinite(e.y));
            EXPECT_TRUE(std::isfinite(burleyDiffuseAlbedo(v, r)));
            EXPECT_TRUE(std::isfinite(ggxAlbedoTerms(0.5f, v).y));
            EXPECT_EQ(ibl.dfgAt(v, r), glm::vec2(0.25f, 0.75f));
        }
        EXPECT_TRUE(std::isfinite(ggxAverageAlbedo(v)));
        EXPECT_TRUE(std::isfinite(diffuseFresnelTransmission(v)));
        EXPECT_EQ(ibl.prefiltered(glm::vec3(v, 0.0f, 0.0f), v), glm::vec3(0.5f));
        EXPECT_EQ(level.bilinear(glm::vec2(v, v)), glm::vec3(0.5f));
    }
    // NaN reads the first entry: the grazing view, roughness 0.
    EXPECT_EQ(ggxAlbedoTerms(NAN, NAN), ggxAlbedoTerms(0.0f, 0.0f));
}
