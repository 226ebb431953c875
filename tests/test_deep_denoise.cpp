// The denoiser on deep G-buffers: a box on a floor under a sky with a sun, seen through one
// small Blend pane, lit at 16 environment and AO rays. Away from the pane the deep frame is
// the flat frame bit for bit; elsewhere its error against a 1024-ray reference is the flat
// frame's, under the per-sample estimate's, behind the pane too; its mean is the
// reference's; and neither the thread count nor the bands it is lit in change a bit.
#include "scene_builder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <dhdr/deferred/denoise/denoise_inputs.h>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/integrator/estimate_carry.h>
#include <gtest/gtest.h>
#include <vector>

using namespace dhdr;
using namespace dhdr::test;

namespace {

[[maybe_unused]] auto* const kKernel = ::testing::AddGlobalTestEnvironment(new EmbreeKernel);

constexpr int W = 160, H = 120;

// The Denoise test's box on a floor, and a pane (material 1: Blend, alpha 0.4) standing in
// front of the box's corner, over about a tenth of the view.
Scene paneScene() {
    Scene scene = emptyScene();
    addFloor(scene, 3.0f);
    addBox(scene, {-0.3f, 0.0f, -0.3f}, {0.3f, 0.7f, 0.3f});
    Material glass;
    glass.name = "glass";
    glass.baseColor = glm::vec3(0.3f, 0.5f, 0.9f);
    glass.roughness = 0.4f;
    glass.metallic = 0.0f;
    glass.alpha = 0.4f;
    glass.alphaMode = AlphaMode::Blend;
    scene.materials.push_back(glass);
    addQuad(scene, {0.2f, 0.1f, 0.7f}, {0.7f, 0.1f, 0.5f}, {0.7f, 0.5f, 0.5f}, {0.2f, 0.5f, 0.7f},
            1);
    return scene;
}

const Camera kCamera = Camera::lookAt({1.5, 2.2, 2.6}, {0.0, 0.2, 0.0}, {0, 1, 0}, 0.8);

DeepGBuffer deepOf(const Scene& scene) {
    GBufferParams p;
    p.width = W;
    p.height = H;
    DeepGBuffer g;
    EXPECT_TRUE(GBufferRenderer(scene, kCamera, p).renderDeep(g, {}, 0));
    return g;
}

ImageBuf shadeDeep(const DeepGBuffer& g, const Light& light, const Visibility& caster,
                   LightingParams p, int nthreads = 2) {
    ImageBuf out;
    EXPECT_TRUE(shadeGBuffer(out, g, {{light}, &caster}, p, {}, nthreads)) << out.geterror();
    return out;
}

LightingParams sixteenRays() {
    LightingParams p;
    p.environmentSamples = 16;
    p.aoSamples = 16;
    p.aoDistance = 0.5f;
    return p;
}

// RMS of channel G against `reference` and the mean of both, over the pixels `in` picks.
struct Error {
    double rms = 0.0, mean = 0.0, referenceMean = 0.0;
    int pixels = 0;
};
template <class Pick>
Error errorOf(const ImageBuf& img, const ImageBuf& reference, Pick in) {
    Error e;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            if (!in(x, y)) continue;
            const double v = px(img, x, y)[1], r = px(reference, x, y)[1];
            e.rms += (v - r) * (v - r);
            e.mean += v;
            e.referenceMean += r;
            ++e.pixels;
        }
    e.rms = std::sqrt(e.rms / std::max(e.pixels, 1));
    e.mean /= std::max(e.pixels, 1);
    e.referenceMean /= std::max(e.pixels, 1);
    return e;
}

struct Frames {
    Scene scene = paneScene();
    RayCaster caster{scene};
    Light light;
    DeepGBuffer deep = deepOf(scene);
    ImageBuf flat = gbufferOf(scene, kCamera, W, H);
    // Pixels with more than one sample (the pane's), and those within the filter's reach of
    // one (Chebyshev distance ≤ kDenoiseReach).
    std::vector<unsigned char> pane, nearPane;

    Frames() {
        light.type = LightType::Environment;
        light.ibl = skyWithSun(glm::normalize(glm::vec3(0.5f, 1.0f, 0.2f)), 1.0f);
        pane.assign(size_t(W) * H, 0);
        nearPane.assign(size_t(W) * H, 0);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                if (deep.samples(x, y) < 2) continue;
                pane[size_t(y) * W + size_t(x)] = 1;
                for (int v = std::max(0, y - kDenoiseReach);
                     v <= std::min(H - 1, y + kDenoiseReach); ++v)
                    for (int u = std::max(0, x - kDenoiseReach);
                         u <= std::min(W - 1, x + kDenoiseReach); ++u)
                        nearPane[size_t(v) * W + size_t(u)] = 1;
            }
    }
    bool covered(int x, int y) const { return deep.samples(x, y) > 0; }
    bool behindPane(int x, int y) const { return pane[size_t(y) * W + size_t(x)] != 0; }
    bool awayFromPane(int x, int y) const { return !nearPane[size_t(y) * W + size_t(x)]; }
};

} // namespace

TEST(DeepDenoise, AsCleanAsTheFlatFrameAndUnbiased) {
    const Frames f;
    int panePixels = 0, away = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            panePixels += f.behindPane(x, y);
            away += f.covered(x, y) && f.awayFromPane(x, y);
        }
    ASSERT_GT(panePixels, 300); // a few percent of the view
    ASSERT_LT(panePixels, W * H / 5);
    ASSERT_GT(away, 3000);

    LightingParams p = sixteenRays();
    const ImageBuf deep = shadeDeep(f.deep, f.light, f.caster, p);
    const ImageBuf flat = shade(f.flat, {f.light}, &f.caster, p, 2);
    p.denoise = false;
    const ImageBuf deepRaw = shadeDeep(f.deep, f.light, f.caster, p);
    const ImageBuf flatRaw = shade(f.flat, {f.light}, &f.caster, p, 2);
    p.environmentSamples = p.aoSamples = 1024;
    const ImageBuf deepReference = shadeDeep(f.deep, f.light, f.caster, p);
    const ImageBuf flatReference = shade(f.flat, {f.light}, &f.caster, p, 2);

    // (a) Beyond the filter's reach of the pane, layer 0 is the flat frame's guide and seeds:
    // the same bits, the per-sample estimate's too.
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            if (!f.awayFromPane(x, y)) continue;
            for (int c = 0; c < 4; ++c) {
                ASSERT_EQ(px(deep, x, y)[c], px(flat, x, y)[c]) << x << "," << y << " c" << c;
                ASSERT_EQ(px(deepRaw, x, y)[c], px(flatRaw, x, y)[c]) << x << "," << y;
            }
        }

    // (b) Over the pixels not behind the pane, as clean as the flat frame against its own
    // reference, and far cleaner than undenoised.
    auto notBehind = [&](int x, int y) { return f.covered(x, y) && !f.behindPane(x, y); };
    const Error deepError = errorOf(deep, deepReference, notBehind),
                flatError = errorOf(flat, flatReference, notBehind),
                rawError = errorOf(deepRaw, deepReference, notBehind);
    // (c) Behind the pane: both samples filtered, each in its layer.
    auto behind = [&](int x, int y) { return f.behindPane(x, y); };
    const Error paneError = errorOf(deep, deepReference, behind),
                paneRawError = errorOf(deepRaw, deepReference, behind);
    std::printf("RMS error at 16 rays, not behind the pane: deep %.5f, flat %.5f, deep "
                "undenoised %.5f; behind the pane (%d pixels): deep %.5f, undenoised %.5f\n",
                deepError.rms, flatError.rms, rawError.rms, paneError.pixels, paneError.rms,
                paneRawError.rms);
    EXPECT_LE(deepError.rms, flatError.rms * 1.05);
    EXPECT_LT(deepError.rms, rawError.rms / 2.5);
    EXPECT_LT(paneError.rms, paneRawError.rms / 2.0);

    // (d) The mean. Behind the pane, within four standard errors of the reference's (the
    // per-sample estimate's spread over √N pixels, its pixels being independent). Over the rest,
    // the filter's own bias at contact shadows (the flat frame's, ~0.4 % here: ten such standard
    // errors) is there too: no further than the flat frame's mean from its reference, plus
    // four standard errors.
    const Error flatRaw16 = errorOf(flatRaw, flatReference, notBehind);
    const double standardError = rawError.rms / std::sqrt(double(rawError.pixels)),
                 paneStandardError = paneRawError.rms / std::sqrt(double(paneRawError.pixels));
    std::printf("mean not behind the pane: deep %.5f, flat %.5f, flat undenoised %.5f; references "
                "%.5f, %.5f (standard error %.5f); behind it: %.5f vs %.5f (standard error %.5f)\n",
                deepError.mean, flatError.mean, flatRaw16.mean, deepError.referenceMean,
                flatError.referenceMean, standardError, paneError.mean, paneError.referenceMean,
                paneStandardError);
    EXPECT_LE(std::abs(deepError.mean - deepError.referenceMean),
              std::abs(flatError.mean - flatError.referenceMean) + 4.0 * standardError);
    EXPECT_NEAR(paneError.mean, paneError.referenceMean, 4.0 * paneStandardError);
}

TEST(DeepDenoise, DoesNotDependOnTheThreadCount) {
    const Frames f;
    const LightingParams p = sixteenRays();
    const ImageBuf one = shadeDeep(f.deep, f.light, f.caster, p, 1);
    const ImageBuf two = shadeDeep(f.deep, f.light, f.caster, p, 2);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 4; ++c)
                ASSERT_EQ(px(one, x, y)[c], px(two, x, y)[c]) << x << "," << y;
}

// As dhdr-light lights a deep file: bands of rows read with kDenoiseReach rows around them
// (clamped to the frame), the estimates the bands share carried from one to the next; every
// pixel, and every ray count, is the whole frame's.
TEST(DeepDenoise, BandsWithTheHaloEqualTheWholeFrame) {
    const Frames f;
    LightingParams p = sixteenRays();
    LightingStats wholeStats;
    ImageBuf whole;
    ASSERT_TRUE(shadeGBuffer(whole, f.deep, {{f.light}, &f.caster}, p, {}, 2, &wholeStats));
    p.frame = OIIO::get_roi(f.deep.spec);
    EstimateCarry carry;
    LightingInputs inputs{{f.light}, &f.caster};
    inputs.carry = &carry;
    const int rows = 2 * p.tileSize; // 32: bands of 32, 32, 32 and 24 rows
    long long shadowRays = 0;
    for (int y = 0; y < H; y += rows) {
        const int y0 = std::max(0, y - kDenoiseReach), y1 = std::min(H, y + rows + kDenoiseReach);
        DeepGBuffer band;
        band.spec = f.deep.spec;
        band.spec.y = y0;
        band.spec.height = y1 - y0;
        const size_t from = f.deep.first[f.deep.pixel(0, y0)],
                     to = f.deep.first[f.deep.pixel(0, y1)];
        for (size_t i = f.deep.pixel(0, y0); i <= f.deep.pixel(0, y1); ++i)
            band.first.push_back(f.deep.first[i] - std::uint32_t(from));
        const size_t nch = size_t(f.deep.spec.nchannels);
        band.values.assign(f.deep.values.begin() + std::ptrdiff_t(from * nch),
                           f.deep.values.begin() + std::ptrdiff_t(to * nch));
        ImageBuf lit;
        LightingStats stats;
        const OIIO::ROI own(0, W, y, std::min(H, y + rows));
        ASSERT_TRUE(shadeGBuffer(lit, band, inputs, p, own, 2, &stats)) << lit.geterror();
        shadowRays += stats.shadowRays;
        for (int yy = own.ybegin; yy < own.yend; ++yy)
            for (int x = 0; x < W; ++x)
                for (int c = 0; c < 4; ++c)
                    ASSERT_EQ(px(lit, x, yy)[c], px(whole, x, yy)[c]) << x << "," << yy;
    }
    EXPECT_EQ(shadowRays, wholeStats.shadowRays); // the shared rows traced once
}
