// Image-based lighting against independent answers: Blender's equirect orientation, furnaces,
// quadrature in double of the irradiance, the GGX lobe and the DFG integrals.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <dhdr/deferred/brdf.h>
#include <dhdr/deferred/environment.h>
#include <dhdr/deferred/ibl.h>
#include <dhdr/deferred/light_eval.h>
#include <dhdr/deferred/lights.h>
#include <dhdr/deferred/sampling.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <gtest/gtest.h>

using namespace dhdr;

namespace {

EnvironmentImage makeEnvironment(int width, const std::function<glm::vec3(glm::vec3)>& radiance) {
    EnvironmentImage env;
    env.width = width;
    env.height = width / 2;
    env.rgb.resize(size_t(env.width) * size_t(env.height) * 3);
    for (int y = 0; y < env.height; ++y)
        for (int x = 0; x < env.width; ++x) {
            const glm::vec3 d = equirectDirection(
                {(float(x) + 0.5f) / float(env.width), (float(y) + 0.5f) / float(env.height)});
            const glm::vec3 L = radiance(d);
            for (int c = 0; c < 3; ++c)
                env.rgb[3 * (size_t(y) * size_t(env.width) + size_t(x)) + size_t(c)] = L[c];
        }
    return env;
}

// A smooth sky: brighter and bluer up, warmer towards +X.
glm::vec3 gradientSky(glm::vec3 d) {
    return glm::vec3(0.6f, 0.7f, 0.9f) + glm::vec3(0.3f, 0.35f, 0.6f) * d.y +
           glm::vec3(0.2f, 0.1f, 0.0f) * d.x * d.x;
}

Ibl bake(const EnvironmentImage& env, int nthreads = 0) {
    Ibl ibl;
    std::string error;
    EXPECT_TRUE(bakeIbl(env, IblBakeParams{}, ibl, error, nthreads)) << error;
    return ibl;
}

} // namespace

TEST(Environment, BlendersEquirectOrientation) {
    // Blender's Environment Texture (Z up): u = 0.5 − atan2(y, x) / 2π, v = 0.5 +
    // atan2(z, hypot(x, y)) / π from the bottom; glTF's frame is Blender's (x, z, −y).
    for (const glm::vec3 b : {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0.3f, -0.5f, 0.8f),
                              glm::vec3(-0.7f, 0.2f, -0.3f)}) {
        const glm::vec3 n = glm::normalize(b);
        const float u = 0.5f - std::atan2(n.y, n.x) / (2.0f * kPi);
        const float t = 1.0f - (0.5f + std::atan2(n.z, std::hypot(n.x, n.y)) / kPi);
        const glm::vec3 gltf(n.x, n.z, -n.y);
        const glm::vec2 uv = equirectUV(gltf);
        EXPECT_NEAR(std::fmod(uv.x - u + 1.0f, 1.0f), 0.0f, 1e-5f) << b.x << b.y << b.z;
        EXPECT_NEAR(uv.y, t, 1e-5f);
        const glm::vec3 back = equirectDirection(uv);
        EXPECT_NEAR(glm::length(back - gltf), 0.0f, 1e-5f);
    }
}

TEST(Environment, ASunOfKnownDirectionLightsTheSurfaceFacingIt) {
    // A sun placed where Blender puts the direction (Blender) 0.5, −0.6, 0.62: glTF
    // (0.5, 0.62, 0.6) normalized.
    const glm::vec3 sunGltf = glm::normalize(glm::vec3(0.5f, 0.62f, 0.6f));
    const glm::vec3 blender(sunGltf.x, -sunGltf.z, sunGltf.y);
    const float u = 0.5f - std::atan2(blender.y, blender.x) / (2.0f * kPi);
    const float t = 1.0f - (0.5f + std::atan2(blender.z, std::hypot(blender.x, blender.y)) / kPi);
    EnvironmentImage env = makeEnvironment(512, [](glm::vec3) { return glm::vec3(0.01f); });
    const int sx = int(u * 512), sy = int(t * 256);
    for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx)
            for (int c = 0; c < 3; ++c)
                env.rgb[3 * (size_t(sy + dy) * 512 + size_t(sx + dx)) + size_t(c)] = 1000.0f;
    EXPECT_GT(env.radiance(sunGltf).r, 500.0f);
    const Ibl ibl = bake(env);
    // The normal that gathers most irradiance, searched over a fine set, is the sun's.
    glm::vec3 best(0.0f);
    float most = -1.0f;
    for (int i = 0; i < 20000; ++i) {
        const glm::vec2 s = hammersley(std::uint32_t(i), 20000, 0);
        const glm::vec3 n = equirectDirection(s);
        const float e = ibl.irradiance(n).r;
        if (e > most) {
            most = e;
            best = n;
        }
    }
    EXPECT_GT(glm::dot(best, sunGltf), 0.98f);
    // Turning the light by 90° about +Y moves the sun from d to R_y(90°) d.
    Light light;
    light.type = LightType::Environment;
    light.rotation = kPi / 2;
    const glm::vec3 turned(sunGltf.z, sunGltf.y, -sunGltf.x);
    EXPECT_GT(env.radiance(intoEnvironment(light, turned)).r, 500.0f);
}

TEST(Environment, SamplerDrawsEachTexelByItsLuminanceTimesSolidAngle) {
    // A sky with a sun: the sampler's histogram over texels and the density it reports against
    // luminance × solid angle computed here in double, independently of its alias tables.
    const EnvironmentImage env = makeEnvironment(64, [](glm::vec3 d) {
        const float sun =
            glm::dot(d, glm::normalize(glm::vec3(0.4f, 0.7f, 0.3f))) > 0.995f ? 500.0f : 0.0f;
        return gradientSky(d) + glm::vec3(sun);
    });
    EnvironmentSampler sampler;
    sampler.build(env);
    ASSERT_FALSE(sampler.empty());
    const int W = env.width, H = env.height;
    std::vector<double> expected(size_t(W) * size_t(H));
    double total = 0.0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const glm::vec3 L = env.texel(x, y);
            const double w = (0.2126 * L.r + 0.7152 * L.g + 0.0722 * L.b) * env.texelSolidAngle(y);
            expected[size_t(y) * size_t(W) + size_t(x)] = w;
            total += w;
        }
    const int n = 1 << 21;
    std::vector<double> count(expected.size(), 0.0);
    int wrongDensity = 0, wrongRadiance = 0;
    for (int i = 0; i < n; ++i) {
        float pdf = 0.0f;
        glm::vec3 radiance;
        const glm::vec3 d =
            sampler.sample(hammersley(std::uint32_t(i), std::uint32_t(n), 7), pdf, radiance);
        ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
        const glm::vec2 uv = equirectUV(d);
        const int x = std::clamp(int(uv.x * float(W)), 0, W - 1),
                  y = std::clamp(int(uv.y * float(H)), 0, H - 1);
        const size_t k = size_t(y) * size_t(W) + size_t(x);
        count[k] += 1.0;
        const double p = expected[k] / total / env.texelSolidAngle(y);
        // A direction rounded onto a texel edge may land in its neighbour; those are rare.
        wrongDensity += std::abs(pdf - p) > 1e-3 * p;
        wrongRadiance += radiance != env.texel(x, y);
    }
    EXPECT_LT(wrongDensity, n / 1000);
    EXPECT_LT(wrongRadiance, n / 1000);
    double worst = 0.0;
    for (size_t k = 0; k < count.size(); ++k) {
        const double p = expected[k] / total;
        const double sigma = std::sqrt(n * p * (1.0 - p)) + 1.0;
        worst = std::max(worst, std::abs(count[k] - n * p) / sigma);
    }
    EXPECT_LT(worst, 6.0) << "a texel drawn more or less often than its share";
}

TEST(Ibl, WhiteFurnace) {
    const float L = 0.8f;
    const Ibl ibl = bake(makeEnvironment(128, [&](glm::vec3) { return glm::vec3(L); }));
    PbrSurface lambert;
    lambert.baseColor = glm::vec3(1.0f);
    lambert.metallic = 0.0f;
    PbrSurface metal = lambert;
    metal.metallic = 1.0f;
    const glm::vec3 N(0.0f, 1.0f, 0.0f);
    for (int r = 0; r <= 10; ++r) {
        lambert.roughness = metal.roughness = float(r) / 10.0f;
        for (const float NdotV : {0.1f, 0.5f, 0.9f, 1.0f}) {
            const glm::vec3 V(std::sqrt(1.0f - NdotV * NdotV), NdotV, 0.0f);
            EXPECT_NEAR(shadeIbl(ibl, lambert, N, V).diffuse.r, L, 1e-5f * L);
            EXPECT_NEAR(shadeIbl(ibl, metal, N, V).specular.r, L, 0.01f * L)
                << "roughness " << lambert.roughness << ", N·V " << NdotV;
        }
    }
}

TEST(Ibl, IrradianceSHAgainstQuadrature) {
    for (const bool sun : {false, true}) {
        const EnvironmentImage env = makeEnvironment(512, [&](glm::vec3 d) {
            glm::vec3 L = gradientSky(d);
            if (sun && glm::dot(d, glm::normalize(glm::vec3(0.3f, 0.8f, 0.2f))) > 0.9995f)
                L += glm::vec3(3000.0f);
            return L;
        });
        const Ibl ibl = bake(env);
        double worst = 0.0, largest = 0.0;
        for (int i = 0; i < 64; ++i) {
            const glm::vec3 n = equirectDirection(hammersley(std::uint32_t(i), 64, 5));
            // E(n) = ∫ L max(n·l, 0) dω over the texels, in double.
            double e = 0.0;
            for (int y = 0; y < env.height; ++y) {
                const double omega = env.texelSolidAngle(y);
                for (int x = 0; x < env.width; ++x) {
                    const glm::vec3 l =
                        equirectDirection({(x + 0.5f) / env.width, (y + 0.5f) / env.height});
                    e += double(env.texel(x, y).r) * std::max(0.0, double(glm::dot(n, l))) * omega;
                }
            }
            worst = std::max(worst, std::abs(double(ibl.irradiance(n).r) - e));
            largest = std::max(largest, e);
        }
        std::printf("SH9 irradiance, %s: largest error %.4f of the maximum\n",
                    sun ? "sky with a sun" : "smooth sky", worst / largest);
        if (!sun) {
            EXPECT_LT(worst, 0.01 * largest);
        }
    }
}

TEST(Ibl, PrefilteredAgainstBruteForceGgx) {
    const EnvironmentImage env = makeEnvironment(512, gradientSky);
    const Ibl ibl = bake(env);
    for (const float roughness : {0.1f, 0.3f, 0.6f, 1.0f}) {
        const float alpha = std::max(roughness * roughness, kMinAlpha);
        double worst = 0.0;
        for (int i = 0; i < 16; ++i) {
            const glm::vec3 R = equirectDirection(hammersley(std::uint32_t(i), 16, 9));
            glm::vec3 t, b;
            orthonormalBasis(R, t, b);
            // Σ L(l) (n·l) D(h) dω over a fine uniform grid of the hemisphere about R, in
            // double, read from the full-resolution environment: no importance sampling, no
            // mips.
            const int n = roughness < 0.2f ? 1200 : 400;
            double sum = 0.0, weight = 0.0;
            for (int a = 0; a < n; ++a) {
                const double cosTheta = 1.0 - (a + 0.5) / n; // uniform in cos θ
                const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
                for (int c = 0; c < n; ++c) {
                    const double phi = 2.0 * M_PI * (c + 0.5) / n;
                    const glm::vec3 local(float(sinTheta * std::cos(phi)),
                                          float(sinTheta * std::sin(phi)), float(cosTheta));
                    const glm::vec3 h = glm::normalize(local + glm::vec3(0, 0, 1));
                    const double w = cosTheta * ggxDistribution(h.z, alpha);
                    const glm::vec3 l = t * local.x + b * local.y + R * local.z;
                    sum += w * env.radiance(l).g;
                    weight += w;
                }
            }
            const double expected = sum / weight;
            worst =
                std::max(worst, std::abs(ibl.prefiltered(R, roughness).g - expected) / expected);
        }
        std::printf("prefiltered vs brute force, roughness %.1f: largest error %.4f\n", roughness,
                    worst);
        EXPECT_LT(worst, 0.02) << "roughness " << roughness;
    }
}

TEST(Ibl, DfgAgainstQuadrature) {
    const Ibl ibl = bake(makeEnvironment(64, [](glm::vec3) { return glm::vec3(1.0f); }));
    for (const float roughness : {0.35f, 0.6f, 1.0f})
        for (const float NdotV : {0.2f, 0.5f, 0.9f}) {
            const float alpha = roughness * roughness;
            const glm::vec3 V(std::sqrt(1.0f - NdotV * NdotV), 0.0f, NdotV);
            // ∫ D Vis (n·l) dω and the same weighted by (1 − v·h)⁵, over a θ, φ grid in double.
            const int n = 1000;
            double x = 0.0, y = 0.0;
            for (int a = 0; a < n; ++a) {
                const double theta = (a + 0.5) / n * M_PI / 2;
                for (int c = 0; c < 2 * n; ++c) {
                    const double phi = (c + 0.5) / (2 * n) * 2 * M_PI;
                    const glm::vec3 L(float(std::sin(theta) * std::cos(phi)),
                                      float(std::sin(theta) * std::sin(phi)),
                                      float(std::cos(theta)));
                    const glm::vec3 H = glm::normalize(L + V);
                    const double f = double(ggxDistribution(H.z, alpha)) *
                                     smithGgxCorrelatedVisibility(L.z, NdotV, alpha) * L.z *
                                     std::sin(theta) * (M_PI / 2 / n) * (M_PI / n);
                    y += f;
                    x += f * std::pow(1.0 - glm::dot(V, H), 5.0);
                }
            }
            const glm::vec2 table = ibl.dfgAt(NdotV, roughness);
            EXPECT_NEAR(table.y, y, 0.01) << roughness << " " << NdotV;
            EXPECT_NEAR(table.x, x, 0.01) << roughness << " " << NdotV;
        }
}

TEST(Ibl, BakingDoesNotDependOnTheThreadCount) {
    const EnvironmentImage env = makeEnvironment(256, gradientSky);
    const Ibl a = bake(env, 1), b = bake(env, 2);
    for (int i = 0; i < 9; ++i)
        EXPECT_EQ(a.sh[size_t(i)], b.sh[size_t(i)]);
    for (size_t k = 0; k < a.levels.size(); ++k)
        EXPECT_EQ(a.levels[k].rgb, b.levels[k].rgb);
    EXPECT_EQ(a.dfg, b.dfg);
}

TEST(Ibl, BakedFileReadsBackAsBaked) {
    const std::string dir = std::filesystem::temp_directory_path() / "dhdr_ibl_test";
    std::filesystem::create_directories(dir);
    const Ibl ibl = bake(makeEnvironment(128, gradientSky));
    std::string error;
    ASSERT_TRUE(writeIbl(dir + "/sky.ibl.exr", ibl, error)) << error;
    Ibl back;
    bool baked = true;
    ASSERT_TRUE(loadIbl(dir + "/sky.ibl.exr", IblBakeParams{}, back, baked, error)) << error;
    EXPECT_FALSE(baked);
    EXPECT_EQ(back.levels.size(), ibl.levels.size());
    for (size_t k = 0; k < ibl.levels.size(); ++k)
        EXPECT_EQ(back.levels[k].rgb, ibl.levels[k].rgb);
    EXPECT_EQ(back.dfg, ibl.dfg);
    for (int i = 0; i < 9; ++i)
        EXPECT_EQ(back.sh[size_t(i)], ibl.sh[size_t(i)]);
    std::filesystem::remove_all(dir);
}

TEST(Ibl, BadEnvironmentsAreClearErrors) {
    const std::string dir = std::filesystem::temp_directory_path() / "dhdr_ibl_bad";
    std::filesystem::create_directories(dir);
    // Not 2:1.
    OIIO::ImageBuf square(OIIO::ImageSpec(64, 64, 3, OIIO::TypeDesc::FLOAT));
    ASSERT_TRUE(square.write(dir + "/square.exr"));
    std::ofstream(dir + "/lights.json")
        << R"({"lights": [{"type": "environment", "name": "sky", "image": "square.exr"}]})";
    std::vector<Light> lights;
    std::vector<std::string> warnings;
    std::string error;
    EXPECT_FALSE(readLightsFile(dir + "/lights.json", lights, error, warnings));
    EXPECT_NE(error.find("lights.json"), std::string::npos) << error;
    EXPECT_NE(error.find("\"sky\""), std::string::npos) << error;
    EXPECT_NE(error.find("square.exr"), std::string::npos) << error;
    EXPECT_NE(error.find("twice as wide"), std::string::npos) << error;
    // Missing.
    std::ofstream(dir + "/missing.json")
        << R"({"lights": [{"type": "environment", "image": "nope.hdr"}]})";
    EXPECT_FALSE(readLightsFile(dir + "/missing.json", lights, error, warnings));
    EXPECT_NE(error.find("nope.hdr"), std::string::npos) << error;
    EXPECT_NE(error.find("light 0"), std::string::npos) << error;
    // NaN and Inf texels: counted and replaced.
    OIIO::ImageBuf bad(OIIO::ImageSpec(64, 32, 3, OIIO::TypeDesc::FLOAT));
    OIIO::ImageBufAlgo::fill(bad, {0.5f, 0.5f, 0.5f});
    const float nan[3] = {NAN, INFINITY, 1.0f};
    bad.setpixel(3, 4, nan);
    ASSERT_TRUE(bad.write(dir + "/bad.exr"));
    std::ofstream(dir + "/nan.json")
        << R"({"lights": [{"type": "environment", "image": "bad.exr"}]})";
    warnings.clear();
    ASSERT_TRUE(readLightsFile(dir + "/nan.json", lights, error, warnings)) << error;
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("2 NaN or infinite"), std::string::npos) << warnings[0];
    ASSERT_EQ(lights.size(), 1u);
    EXPECT_TRUE(std::isfinite(lights[0].ibl->irradiance({0, 1, 0}).r));
    std::filesystem::remove_all(dir);
}
