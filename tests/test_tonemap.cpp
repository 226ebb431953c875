// libtonemap against hand-computed values (numbers worked out with a calculator, not with the
// code under test).
#include "../libtonemap/src/rgb_plane.h"

#include <OpenImageIO/imagebuf.h>
#include <array>
#include <cmath>
#include <cstring>
#include <dhdr/io/sanitize.h>
#include <dhdr/tonemap/bloom.h>
#include <dhdr/tonemap/edge_aa.h>
#include <dhdr/tonemap/luminance.h>
#include <dhdr/tonemap/reinhard.h>
#include <gtest/gtest.h>
#include <random>

using namespace dhdr;
using OIIO::ImageBuf;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

ImageBuf floatImage(int w, int h, int nch) {
    ImageBuf img(ImageSpec(w, h, nch, TypeDesc::FLOAT));
    return img;
}

float* px(ImageBuf& img, int x, int y) {
    return static_cast<float*>(img.pixeladdr(x, y));
}
const float* px(const ImageBuf& img, int x, int y) {
    return static_cast<const float*>(img.pixeladdr(x, y));
}

// Grey pixels of luminance 0.1, 1, 10, 100 (the seed weights sum to 1).
ImageBuf fourGreys() {
    ImageBuf img = floatImage(2, 2, 3);
    const float v[4] = {0.1f, 1.0f, 10.0f, 100.0f};
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c)
            px(img, i % 2, i / 2)[c] = v[i];
    return img;
}

} // namespace

TEST(Luminance, LogAverageMatchesHandComputedValue) {
    LuminanceStats stats;
    ASSERT_TRUE(computeLuminanceStats(stats, fourGreys()));
    // exp(¼ Σ ln(1e-4 + Lw)) for Lw = 0.1, 1, 10, 100.
    EXPECT_NEAR(stats.logAverage, 3.1631557056521333, 1e-6);
    EXPECT_DOUBLE_EQ(stats.maxLuminance, 100.0);
    EXPECT_EQ(stats.pixels, 4);
}

TEST(Luminance, LogAverageIsNotTheSeedsLog2ThenExpMisprint) {
    // The seed takes log2 and then exp, which gives 5.2665 here; the geometric mean with
    // δ → 0 is (0.1 · 1 · 10 · 100)^¼ = 3.16228.
    LuminanceStatsParams p;
    p.delta = 1e-12;
    LuminanceStats stats;
    computeLuminanceStats(stats, fourGreys(), p);
    EXPECT_NEAR(stats.logAverage, std::pow(100.0, 0.25), 1e-6);
    EXPECT_GT(std::abs(stats.logAverage - 5.266492461846018), 1.0);
}

TEST(Luminance, WeightsAreSelectable) {
    ImageBuf img = floatImage(1, 1, 3);
    px(img, 0, 0)[0] = 1.0f; // pure red
    LuminanceStats seed, rec709;
    computeLuminanceStats(seed, img);
    LuminanceStatsParams p;
    p.weights = kRec709LuminanceWeights;
    computeLuminanceStats(rec709, img, p);
    EXPECT_NEAR(seed.maxLuminance, 0.27, 1e-7);
    EXPECT_NEAR(rec709.maxLuminance, 0.2126, 1e-7);
}

TEST(Luminance, NonFinitePixelsAreLeftOutOfTheAverage) {
    ImageBuf img = fourGreys();
    ImageBuf bigger = floatImage(3, 2, 3);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x)
            std::memcpy(px(bigger, x, y), px(img, x, y), 12);
    px(bigger, 2, 0)[1] = NAN;
    px(bigger, 2, 1)[0] = INFINITY;
    LuminanceStats stats;
    computeLuminanceStats(stats, bigger);
    EXPECT_EQ(stats.nonFinitePixels, 2);
    EXPECT_NEAR(stats.logAverage, 3.1631557056521333, 1e-6);
}

TEST(Luminance, ResultDoesNotDependOnThreadCount) {
    ImageBuf img = floatImage(333, 257, 3);
    std::mt19937 rng(7);
    for (int y = 0; y < 257; ++y)
        for (int x = 0; x < 333; ++x)
            for (int c = 0; c < 3; ++c)
                px(img, x, y)[c] = float(rng() % 100000) * 1e-3f;
    LuminanceStats one, two, eight;
    computeLuminanceStats(one, img, {}, {}, 1);
    computeLuminanceStats(two, img, {}, {}, 2);
    computeLuminanceStats(eight, img, {}, {}, 8);
    EXPECT_EQ(one.logAverage, two.logAverage);
    EXPECT_EQ(one.logAverage, eight.logAverage);
}

TEST(Reinhard, MatchesHandComputedValues) {
    ImageBuf out;
    ASSERT_TRUE(reinhard(out, fourGreys()));
    // L = 0.18 / 3.16315570565 · Lw; Lwhite = L(100) = 5.69051974515;
    // Ld = L (1 + L / Lwhite²) / (1 + L); grey in, grey out.
    const double expected[4] = {0.005659315299693897, 0.053935960944239594, 0.369045757514846, 1.0};
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(px(out, i % 2, i / 2)[c], expected[i], 1e-6) << "pixel " << i;
}

TEST(Reinhard, WhitePointMapsToExactlyOne) {
    for (double white : {0.5, 1.0, 3.0, 17.25, 1e4})
        EXPECT_EQ(reinhardCurve(white, white), 1.0);
}

TEST(Reinhard, InfiniteWhiteIsLOverOnePlusL) {
    ReinhardParams p;
    p.white = INFINITY;
    ImageBuf out;
    ASSERT_TRUE(reinhard(out, fourGreys(), p));
    const double expected[4] = {0.005658320958014855, 0.053841345078747466, 0.36267248233822824,
                                0.8505347808404898};
    for (int i = 0; i < 4; ++i)
        EXPECT_NEAR(px(out, i % 2, i / 2)[0], expected[i], 1e-6);
}

TEST(Reinhard, KeepsChromaticityAndAlpha) {
    ImageBuf img = floatImage(2, 1, 4);
    const float a[4] = {2.0f, 1.0f, 0.5f, 0.25f}, b[4] = {0.1f, 0.1f, 0.1f, 1.0f};
    std::memcpy(px(img, 0, 0), a, 16);
    std::memcpy(px(img, 1, 0), b, 16);
    ImageBuf out;
    ASSERT_TRUE(reinhard(out, img));
    const float* q = px(out, 0, 0);
    EXPECT_NEAR(q[0] / q[1], 2.0, 1e-6);
    EXPECT_NEAR(q[2] / q[1], 0.5, 1e-6);
    EXPECT_EQ(q[3], 0.25f);
}

TEST(Reinhard, ExposureIsAFactorOfTwoPerStop) {
    ReinhardParams p;
    p.white = INFINITY;
    p.exposure = 1.0;
    ImageBuf out;
    reinhard(out, fourGreys(), p);
    const double L = 2.0 * 0.05690519745150839; // twice the scaled luminance of Lw = 1
    EXPECT_NEAR(px(out, 1, 0)[0], L / (1.0 + L), 1e-6);
}

TEST(Sanitize, CountsAndReplacesNonFiniteValues) {
    ImageBuf img = floatImage(2, 2, 3);
    px(img, 0, 0)[0] = 4.0f;
    px(img, 1, 0)[0] = NAN;
    px(img, 0, 1)[0] = INFINITY;
    px(img, 1, 1)[0] = -INFINITY;
    px(img, 1, 1)[2] = NAN;
    const NonFiniteCount n = replaceNonFinite(img);
    EXPECT_EQ(n.nan, 2);
    EXPECT_EQ(n.positiveInf, 1);
    EXPECT_EQ(n.negativeInf, 1);
    EXPECT_EQ(px(img, 1, 0)[0], 0.0f);
    EXPECT_EQ(px(img, 0, 1)[0], kInfinityReplacement); // a constant, whatever else was read
    EXPECT_EQ(px(img, 1, 1)[0], 0.0f);
    EXPECT_EQ(px(img, 1, 1)[2], 0.0f);
}

// The rule holds value by value: replacing strip by strip gives the whole image's result.
TEST(Sanitize, ReplacementDoesNotDependOnStrips) {
    ImageBuf whole = floatImage(3, 4, 1);
    const float values[12] = {1.0f,   INFINITY, 7.0f,     2.0f, -INFINITY, NAN,
                              900.0f, 3.0f,     INFINITY, 5.0f, 1e6f,      -2.0f};
    for (int i = 0; i < 12; ++i)
        px(whole, i % 3, i / 3)[0] = values[i];
    ImageBuf strips;
    strips.copy(whole);
    replaceNonFinite(whole);
    for (int y = 0; y < 4; ++y)
        replaceNonFinite(strips, OIIO::ROI(0, 3, y, y + 1, 0, 1, 0, 1));
    for (int i = 0; i < 12; ++i)
        EXPECT_EQ(px(whole, i % 3, i / 3)[0], px(strips, i % 3, i / 3)[0]) << i;
    EXPECT_EQ(px(whole, 1, 0)[0], kInfinityReplacement);
    EXPECT_EQ(px(whole, 2, 2)[0], kInfinityReplacement);
}

namespace {

// A dim 256×256 image with a bright 8×8 square centred on pixel corner (128, 128).
ImageBuf brightSpot() {
    ImageBuf img = floatImage(256, 256, 4);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            float* p = px(img, x, y);
            const bool spot = x >= 124 && x < 132 && y >= 124 && y < 132;
            p[0] = p[1] = p[2] = spot ? 1000.0f : 0.01f;
            p[3] = 0.5f;
        }
    return img;
}

} // namespace

TEST(Bloom, CentredSpotDoesNotShift) {
    ImageBuf layer;
    ASSERT_TRUE(bloomLayer(layer, brightSpot()));
    double sum = 0.0, sx = 0.0, sy = 0.0;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            const double v = px(layer, x, y)[1];
            sum += v;
            sx += v * (x + 0.5);
            sy += v * (y + 0.5);
        }
    ASSERT_GT(sum, 0.0);
    EXPECT_NEAR(sx / sum, 128.0, 1e-3);
    EXPECT_NEAR(sy / sum, 128.0, 1e-3);
    // Symmetric about the centre, pixel by pixel.
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            ASSERT_NEAR(px(layer, x, y)[0], px(layer, 255 - x, 255 - y)[0],
                        1e-5 * (1.0 + px(layer, x, y)[0]));
}

TEST(Bloom, OutputIsInputPlusStrengthTimesLayer) {
    const ImageBuf src = brightSpot();
    BloomParams p;
    ImageBuf layer, out;
    ASSERT_TRUE(bloomLayer(layer, src, p));
    ASSERT_TRUE(bloom(out, src, p));
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            for (int c = 0; c < 3; ++c)
                ASSERT_FLOAT_EQ(px(out, x, y)[c], px(src, x, y)[c] + 1.3f * px(layer, x, y)[c]);
            ASSERT_EQ(px(out, x, y)[3], 0.5f); // alpha passes through
        }
}

TEST(Bloom, ConservesTheEnergyOfTheBrightPass) {
    // The Gaussian is normalized and the resampling preserves the mean, so the layer's total
    // equals the bright pass's total (the spot's energy, 8 × 8 × 1000 per channel) up to the
    // 8-tap box, which also keeps the whole spot.
    ImageBuf layer;
    bloomLayer(layer, brightSpot());
    double sum = 0.0;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            sum += px(layer, x, y)[0];
    EXPECT_NEAR(sum, 64000.0, 64000.0 * 0.02);
}

TEST(Bloom, FlatImageDoesNotBloom) {
    ImageBuf img = floatImage(64, 64, 3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            px(img, x, y)[0] = px(img, x, y)[1] = px(img, x, y)[2] = 5.0f;
    ImageBuf layer;
    bloomLayer(layer, img);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            ASSERT_EQ(px(layer, x, y)[0], 0.0f);
}

namespace {

ImageBuf randomColour(int w, int h, unsigned seed) {
    ImageBuf img = floatImage(w, h, 4);
    std::mt19937 rng(seed);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 4; ++c)
                px(img, x, y)[c] = float(rng() % 1000) * 0.01f;
    return img;
}

} // namespace

TEST(EdgeAA, FlatGeometryLeavesTheImageBitIdentical) {
    const ImageBuf colour = randomColour(64, 48, 1);
    ImageBuf normal = floatImage(64, 48, 3), depth = floatImage(64, 48, 1);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            px(normal, x, y)[2] = 1.0f;
            px(depth, x, y)[0] = 3.0f;
        }
    ImageBuf out;
    ASSERT_TRUE(edgeAA(out, colour, &normal, &depth));
    for (int y = 0; y < 48; ++y)
        ASSERT_EQ(std::memcmp(px(out, 0, y), px(colour, 0, y), 64 * 4 * sizeof(float)), 0);
}

TEST(EdgeAA, ChangesPixelsOnlyAlongADepthEdge) {
    const ImageBuf colour = randomColour(64, 48, 2);
    ImageBuf depth = floatImage(64, 48, 1);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            px(depth, x, y)[0] = x < 32 ? 1.0f : 5.0f;
    ImageBuf out;
    ASSERT_TRUE(edgeAA(out, colour, nullptr, &depth));
    int changed = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            const bool same = std::memcmp(px(out, x, y), px(colour, x, y), 16) == 0;
            if (x == 31 || x == 32) {
                changed += !same;
            } else {
                ASSERT_TRUE(same) << x << "," << y;
            }
        }
    EXPECT_EQ(changed, 2 * 48);
}

TEST(EdgeAA, BlurFactorIsTheSumOfSquaredNormalDifferences) {
    ImageBuf normal = floatImage(3, 3, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x)
            px(normal, x, y)[2] = 1.0f;
    px(normal, 2, 1)[0] = 0.3f; // one neighbour of the centre differs by (0.3, 0, 0)
    EdgeAAParams p;
    p.normalWeight = 2.0f;
    ImageBuf factor;
    ASSERT_TRUE(edgeBlurFactor(factor, &normal, nullptr, p));
    EXPECT_NEAR(px(factor, 1, 1)[0], 2.0 * 0.09, 1e-6);
    EXPECT_EQ(px(factor, 0, 1)[0], 0.0f); // two pixels away
}

TEST(Luminance, TransparentPixelsAreNotMetered) {
    ImageBuf img = floatImage(3, 2, 4);
    const ImageBuf greys = fourGreys();
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) {
            std::memcpy(px(img, x, y), px(greys, x, y), 12);
            px(img, x, y)[3] = 1.0f;
        }
    // Column 2 is background: black and transparent.
    LuminanceStats stats;
    computeLuminanceStats(stats, img);
    EXPECT_EQ(stats.transparentPixels, 2);
    EXPECT_NEAR(stats.logAverage, 3.1631557056521333, 1e-6);
    LuminanceStatsParams all;
    all.skipTransparent = false;
    computeLuminanceStats(stats, img, all);
    // Two more pixels at ln(1e-4): exp((4 ln 3.16316 + 2 ln 1e-4) / 6).
    EXPECT_NEAR(stats.logAverage,
                std::exp((4.0 * std::log(3.1631557056521333) + 2.0 * std::log(1e-4)) / 6.0), 1e-7);
}

// The streaming box downsample (rows fed one at a time, as dhdr-bloom reads strips) equals
// the whole-plane one bit for bit, for sizes that do not divide evenly.
TEST(BoxDownsampler, EqualsTheWholePlane) {
    for (const auto& [w, h, ow, oh] : std::vector<std::array<int, 4>>{
             {37, 23, 9, 5}, {64, 64, 16, 16}, {10, 7, 1, 1}, {33, 90, 8, 22}}) {
        dhdr::detail::RgbPlane src(w, h);
        for (size_t i = 0; i < src.rgb.size(); ++i)
            src.rgb[i] = float((i * 2654435761u) % 1000) / 37.0f;
        const dhdr::detail::RgbPlane whole = dhdr::detail::boxDownsample(src, ow, oh, 2);
        dhdr::detail::BoxDownsampler stream(w, h, ow, oh);
        for (int y = 0; y < h; ++y)
            stream.addRow(y, src.at(0, y), 3);
        EXPECT_EQ(stream.result().rgb, whole.rgb) << w << "x" << h << " -> " << ow << "x" << oh;
    }
}
