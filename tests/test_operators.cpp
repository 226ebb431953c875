// dhdr-tonemap's operators, metering and dithering against references computed here in double
// precision from the published formulas, and against values worked out by hand.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <dhdr/tonemap/adaptation.h>
#include <dhdr/tonemap/local_reinhard.h>
#include <dhdr/tonemap/metering.h>
#include <dhdr/tonemap/quantize.h>
#include <dhdr/tonemap/tone_map.h>
#include <gtest/gtest.h>
#include <vector>

using namespace dhdr;
using OIIO::ImageBuf;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

float* px(ImageBuf& img, int x, int y) {
    return static_cast<float*>(img.pixeladdr(x, y));
}

// One row of grey pixels.
ImageBuf greys(const std::vector<float>& values) {
    ImageBuf img(ImageSpec(int(values.size()), 1, 3, TypeDesc::FLOAT));
    for (size_t i = 0; i < values.size(); ++i)
        for (int c = 0; c < 3; ++c)
            px(img, int(i), 0)[c] = values[i];
    return img;
}

// Metering that makes the scale key / L̄w exactly 1.
LuminanceStats unitScale(double maxLuminance) {
    LuminanceStats s;
    s.logAverage = 0.18;
    s.maxLuminance = maxLuminance;
    s.pixels = 1;
    return s;
}

} // namespace

TEST(Operators, NamesRoundTrip) {
    for (const char* name : {"reinhard", "reinhard-local", "drago", "hable", "pbr-neutral",
                             "exposure", "aces", "agx", "none"}) {
        ToneOperator op;
        ASSERT_TRUE(parseToneOperator(name, op));
        EXPECT_EQ(toneOperatorName(op), name);
    }
    ToneOperator op;
    EXPECT_FALSE(parseToneOperator("aces2", op));
}

TEST(Operators, HableMatchesThePublishedCurve) {
    // f(x) = ((x(Ax + CB) + DE) / (x(Ax + B) + DF)) − E/F with A..F = 0.15, 0.50, 0.10, 0.20,
    // 0.02, 0.30, W = 11.2; out = f(2 v) / f(W).
    auto f = [](double x) {
        const double A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30;
        return (x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F) - E / F;
    };
    const std::vector<float> v = {0.0f, 0.05f, 0.18f, 1.0f, 4.0f, 5.6f};
    const LuminanceStats stats = unitScale(5.6);
    ToneMapParams p;
    p.op = ToneOperator::Hable;
    p.stats = &stats;
    ImageBuf out;
    ASSERT_TRUE(toneMap(out, greys(v), p));
    for (size_t i = 0; i < v.size(); ++i)
        EXPECT_NEAR(px(out, int(i), 0)[1], f(2.0 * v[i]) / f(11.2), 1e-6) << v[i];
    EXPECT_NEAR(px(out, 5, 0)[0], 1.0, 1e-6); // 2 × 5.6 = W: white
}

TEST(Operators, DragoMatchesEquationFourAndMapsTheMaximumToOne) {
    auto drago = [](double Lw, double Lwmax) {
        const double b = 0.85;
        return (100.0 * 0.01 / std::log10(Lwmax + 1.0)) * std::log(Lw + 1.0) /
               std::log(2.0 + 8.0 * std::pow(Lw / Lwmax, std::log(b) / std::log(0.5)));
    };
    const std::vector<float> v = {0.01f, 0.3f, 2.0f, 50.0f};
    const LuminanceStats stats = unitScale(50.0);
    ToneMapParams p;
    p.op = ToneOperator::Drago;
    p.stats = &stats;
    ImageBuf out;
    ASSERT_TRUE(toneMap(out, greys(v), p));
    for (size_t i = 0; i < v.size(); ++i)
        EXPECT_NEAR(px(out, int(i), 0)[0], drago(v[i], 50.0), 1e-6) << v[i];
    // At Lw = Lwmax the denominator is ln 10 and the result (1/log10(Lwmax+1)) ln(Lwmax+1)/ln 10.
    EXPECT_NEAR(px(out, 3, 0)[0], 1.0, 1e-6);
}

TEST(Operators, PbrNeutralMatchesHandComputedValues) {
    ImageBuf img(ImageSpec(2, 1, 3, TypeDesc::FLOAT));
    const float a[3] = {0.5f, 0.5f, 0.5f}, b[3] = {2.0f, 1.0f, 0.5f};
    std::memcpy(px(img, 0, 0), a, 12);
    std::memcpy(px(img, 1, 0), b, 12);
    const LuminanceStats stats = unitScale(2.0);
    ToneMapParams p;
    p.op = ToneOperator::PbrNeutral;
    p.stats = &stats;
    ImageBuf out;
    ASSERT_TRUE(toneMap(out, img, p));
    // Below the compression start only the 0.04 offset applies.
    EXPECT_NEAR(px(out, 0, 0)[0], 0.46, 1e-6);
    // (2, 1, 0.5) − 0.04 → peak 1.96 → new peak 1 − 0.24²/1.44 = 0.96, scaled by 0.96/1.96,
    // then mixed towards 0.96 by g = 1 − 1/1.15.
    EXPECT_NEAR(px(out, 1, 0)[0], 0.96, 1e-5);
    EXPECT_NEAR(px(out, 1, 0)[1], 0.534091, 1e-5);
    EXPECT_NEAR(px(out, 1, 0)[2], 0.321136, 1e-5);
}

TEST(Operators, AgxMatchesThePublishedPolynomialForm) {
    // Inset (rows of the column-major published matrix), log2 window, sigmoid fit, outset,
    // power 2.2, in double.
    const double inset[3][3] = {{0.842479062253094, 0.0784335999999992, 0.0792237451477643},
                                {0.0423282422610123, 0.878468636469772, 0.0791661274605434},
                                {0.0423756549057051, 0.0784336, 0.879142973793104}};
    const double outset[3][3] = {{1.19687900512017, -0.0980208811401368, -0.0990297440797205},
                                 {-0.0528968517574562, 1.15190312990417, -0.0989611768448433},
                                 {-0.0529716355144438, -0.0980434501171241, 1.15107367264116}};
    auto reference = [&](const double rgb[3], double out[3]) {
        double v[3], w[3];
        for (int r = 0; r < 3; ++r) {
            v[r] = inset[r][0] * rgb[0] + inset[r][1] * rgb[1] + inset[r][2] * rgb[2];
            const double ev = std::clamp(std::log2(std::max(v[r], 1e-10)), -12.47393, 4.026069);
            const double x = (ev + 12.47393) / (4.026069 + 12.47393);
            v[r] = 15.5 * std::pow(x, 6) - 40.14 * std::pow(x, 5) + 31.96 * std::pow(x, 4) -
                   6.868 * std::pow(x, 3) + 0.4298 * x * x + 0.1191 * x - 0.00232;
        }
        for (int r = 0; r < 3; ++r) {
            w[r] = outset[r][0] * v[0] + outset[r][1] * v[1] + outset[r][2] * v[2];
            out[r] = std::pow(std::max(w[r], 0.0), 2.2);
        }
    };
    const double samples[4][3] = {
        {0.18, 0.18, 0.18}, {1.0, 0.5, 0.1}, {0.002, 0.01, 0.05}, {16, 12, 4}};
    for (const auto& rgb : samples) {
        double expected[3];
        reference(rgb, expected);
        const glm::vec3 got = agx(glm::vec3(float(rgb[0]), float(rgb[1]), float(rgb[2])));
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], expected[c], 2e-5 * (1.0 + expected[c]));
    }
    // Grey stays grey.
    const glm::vec3 grey = agx(glm::vec3(0.18f));
    EXPECT_NEAR(grey.r, grey.g, 1e-4);
    EXPECT_NEAR(grey.g, grey.b, 1e-4);
}

TEST(Operators, ExposureIsLinearAndClipped) {
    ToneMapParams p;
    p.op = ToneOperator::Exposure;
    p.exposure = 2.0;
    ImageBuf out;
    ASSERT_TRUE(toneMap(out, greys({0.1f, 0.2f, 0.3f, -1.0f}), p));
    EXPECT_FLOAT_EQ(px(out, 0, 0)[0], 0.4f);
    EXPECT_FLOAT_EQ(px(out, 1, 0)[0], 0.8f);
    EXPECT_FLOAT_EQ(px(out, 2, 0)[0], 1.0f);
    EXPECT_FLOAT_EQ(px(out, 3, 0)[0], 0.0f);
}

TEST(Operators, ADestinationWithoutColourChannelsIsAnError) {
    // One channel cannot take the three a colour operator writes (it once wrote past them).
    ImageBuf src(ImageSpec(4, 4, 3, TypeDesc::FLOAT));
    const float grey[3] = {0.5f, 0.5f, 0.5f};
    OIIO::ImageBufAlgo::fill(src, grey);
    ImageBuf dst(ImageSpec(4, 4, 1, TypeDesc::FLOAT));
    ToneMapParams p;
    p.op = ToneOperator::Hable;
    EXPECT_FALSE(toneMap(dst, src, p));
    EXPECT_TRUE(dst.has_error());
}

TEST(Operators, LocalReinhardOnAFlatImageIsTheGlobalCurve) {
    // No activity at any scale: the largest scale is chosen and V1 = L, so Ld = L / (1 + L).
    ImageBuf L(ImageSpec(40, 30, 1, TypeDesc::FLOAT));
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            px(L, x, y)[0] = 2.5f;
    ImageBuf out;
    ASSERT_TRUE(localReinhard(out, L));
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            ASSERT_NEAR(px(out, x, y)[0], 2.5 / 3.5, 1e-6);
}

namespace {

// V1(x, y, s) by direct 2-D summation of the Gaussian of scale s (σ = s/4, window ⌈3σ⌉,
// edges clamped), in double.
double centreSurround(const std::vector<double>& L, int w, int h, int x, int y, double s) {
    const double sigma = s / 4.0;
    const int r = std::max(1, int(std::ceil(3.0 * sigma)));
    double sum = 0.0, weight = 0.0;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const double g = std::exp(-0.5 * (dx * dx + dy * dy) / (sigma * sigma));
            const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
            sum += g * L[size_t(yy * w + xx)];
            weight += g;
        }
    return sum / weight;
}

} // namespace

TEST(Operators, LocalReinhardMatchesDirectCentreSurround) {
    // A bright square on a dim ground: near its edge the activity passes ε at small scales.
    const int w = 48, h = 40;
    std::vector<double> L(size_t(w * h));
    ImageBuf img(ImageSpec(w, h, 1, TypeDesc::FLOAT));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool bright = x >= 20 && x < 30 && y >= 15 && y < 25;
            L[size_t(y * w + x)] = bright ? 8.0 : 0.05 + 0.002 * x;
            px(img, x, y)[0] = float(L[size_t(y * w + x)]);
        }
    LocalReinhardParams params;
    ImageBuf out;
    ASSERT_TRUE(localReinhard(out, img, params));
    int local = 0;
    for (int y = 0; y < h; y += 3)
        for (int x = 0; x < w; x += 3) {
            double chosen = centreSurround(L, w, h, x, y, 1.0);
            for (int i = 0; i < params.scales; ++i) {
                const double s = std::pow(1.6, i);
                const double v1 = centreSurround(L, w, h, x, y, s);
                const double v2 = centreSurround(L, w, h, x, y, 1.6 * s);
                const double activity = (v1 - v2) / (std::pow(2.0, 8.0) * 0.18 / (s * s) + v1);
                if (std::abs(activity) >= 0.05) break;
                chosen = v1;
            }
            const double Lxy = L[size_t(y * w + x)];
            EXPECT_NEAR(px(out, x, y)[0], Lxy / (1.0 + chosen), 1e-5 * (1.0 + Lxy))
                << x << "," << y;
            local += std::abs(chosen - Lxy) > 0.01;
        }
    EXPECT_GT(local, 10); // the surround differs from the pixel: the operator is local
}

TEST(Metering, HistogramWindowIgnoresOutliers) {
    // 92 pixels at 1, 4 at 0.001 and 4 at 1000: the 5–95 % window holds only the ones.
    std::vector<float> v(100, 1.0f);
    for (int i = 0; i < 4; ++i) {
        v[size_t(i)] = 0.001f;
        v[size_t(99 - i)] = 1000.0f;
    }
    MeteringParams p;
    p.mode = MeteringMode::Histogram;
    LuminanceStats stats;
    ASSERT_TRUE(meter(stats, greys(v), p));
    EXPECT_NEAR(stats.logAverage, 1.0001, 1e-6); // exp(ln(δ + 1))
    p.mode = MeteringMode::LogAverage;
    meter(stats, greys(v), p);
    // The plain log-average moves with the outliers: exp((4 ln 0.0011 + 4 ln 1000.0001 + 92
    // ln 1.0001)/100).
    EXPECT_NEAR(
        stats.logAverage,
        std::exp((4 * std::log(0.0011) + 4 * std::log(1000.0001) + 92 * std::log(1.0001)) / 100.0),
        1e-5);
}

TEST(Metering, StripsInPassesEqualTheWholeImage) {
    // A frame of luminances over six decades, some pixels transparent, metered whole and as
    // separate 7-row strips (what dhdr-tonemap streams): the same doubles in both modes.
    ImageBuf frame(ImageSpec(37, 53, 4, TypeDesc::FLOAT));
    uint32_t state = 12345;
    auto next = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    for (int y = 0; y < 53; ++y)
        for (int x = 0; x < 37; ++x) {
            float* p = px(frame, x, y);
            const float scale = std::pow(10.0f, 6.0f * next() - 3.0f);
            for (int c = 0; c < 3; ++c)
                p[c] = scale * next();
            p[3] = next() < 0.1f ? 0.0f : 1.0f;
        }
    for (MeteringMode mode : {MeteringMode::LogAverage, MeteringMode::Histogram}) {
        MeteringParams params;
        params.mode = mode;
        LuminanceStats whole;
        ASSERT_TRUE(meter(whole, frame, params));
        MeteringAccumulator strips(params);
        int passes = 0;
        do {
            for (int y = 0; y < 53; y += 7) {
                OIIO::ROI rows(0, 37, y, std::min(y + 7, 53), 0, 1, 0, 4);
                ImageBuf strip = OIIO::ImageBufAlgo::cut(frame, rows);
                strip.set_origin(0, y);
                ASSERT_TRUE(strips.add(strip));
            }
            strips.endPass();
            ++passes;
        } while (strips.needsAnotherPass());
        EXPECT_EQ(passes, mode == MeteringMode::Histogram ? 3 : 1);
        const LuminanceStats s = strips.result();
        EXPECT_EQ(s.logAverage, whole.logAverage);
        EXPECT_EQ(s.maxLuminance, whole.maxLuminance);
        EXPECT_EQ(s.minLuminance, whole.minLuminance);
        EXPECT_EQ(s.pixels, whole.pixels);
        EXPECT_EQ(s.transparentPixels, whole.transparentPixels);
        EXPECT_GT(whole.transparentPixels, 0);
    }
    // The window matters here, so the comparison above covers the histogram passes.
    MeteringParams histogram;
    histogram.mode = MeteringMode::Histogram;
    LuminanceStats a, b;
    meter(a, frame, histogram);
    meter(b, frame, MeteringParams{});
    EXPECT_GT(std::abs(std::log(a.logAverage / b.logAverage)), 1e-3);
}

TEST(Quantize, DitherIsDeterministicAndUnbiased) {
    auto flat = [](float v) {
        ImageBuf img(ImageSpec(16, 16, 3, TypeDesc::FLOAT));
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                for (int c = 0; c < 3; ++c)
                    px(img, x, y)[c] = v;
        return img;
    };
    // Flat values between two 8-bit levels: the dithered pixels average back to the value (to
    // 1/64 step, the matrix's resolution), where plain rounding is off by up to ½.
    for (double fraction : {0.1, 0.25, 0.5, 0.7, 0.93}) {
        const float v = float((100.0 + fraction) / 255.0);
        const ImageBuf in = flat(v);
        ImageBuf a(ImageSpec(16, 16, 3, TypeDesc::UINT8)), b(a.spec()), plain(a.spec());
        ASSERT_TRUE(quantize(a, in, {}, {}, 1));
        ASSERT_TRUE(quantize(b, in, {}, {}, 2));
        ASSERT_EQ(std::memcmp(a.localpixels(), b.localpixels(), a.spec().image_bytes()), 0);
        QuantizeParams noDither;
        noDither.dither = false;
        ASSERT_TRUE(quantize(plain, in, noDither));
        double mean = 0.0;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                const auto* q = static_cast<const uint8_t*>(a.pixeladdr(x, y));
                EXPECT_TRUE(q[1] == 100 || q[1] == 101) << int(q[1]);
                mean += q[1] / 256.0;
                EXPECT_EQ(static_cast<const uint8_t*>(plain.pixeladdr(x, y))[1],
                          fraction < 0.5 ? 100 : 101);
            }
        EXPECT_NEAR(mean, 100.0 + fraction, 1.0 / 64.0) << fraction;
    }
}

TEST(Quantize, RoundsClampsAndLeavesAlphaUndithered) {
    ImageBuf in(ImageSpec(8, 8, 4, TypeDesc::FLOAT));
    const float values[4] = {-0.5f, 2.0f, 0.5f, 0.25f};
    OIIO::ImageBufAlgo::fill(in, values);
    ImageBuf q16(ImageSpec(8, 8, 4, TypeDesc::UINT16));
    QuantizeParams noDither;
    noDither.dither = false;
    ASSERT_TRUE(quantize(q16, in, noDither));
    const auto* p = static_cast<const uint16_t*>(q16.pixeladdr(3, 5));
    EXPECT_EQ(p[0], 0);
    EXPECT_EQ(p[1], 65535);
    EXPECT_EQ(p[2], 32768); // 0.5 · 65535 = 32767.5 rounds up
    EXPECT_EQ(p[3], 16384); // 16383.75
    ImageBuf q8(ImageSpec(8, 8, 4, TypeDesc::UINT8));
    ASSERT_TRUE(quantize(q8, in));
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) // 63.75 → 64 always: alpha is not dithered
            EXPECT_EQ(static_cast<const uint8_t*>(q8.pixeladdr(x, y))[3], 64);
}

TEST(Quantize, AStripMatchesTheWholeImage) {
    ImageBuf in(ImageSpec(24, 20, 3, TypeDesc::FLOAT));
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 24; ++x)
            for (int c = 0; c < 3; ++c)
                px(in, x, y)[c] = float(x + 3 * y + c) / 90.0f;
    ImageBuf whole(ImageSpec(24, 20, 3, TypeDesc::UINT8));
    ASSERT_TRUE(quantize(whole, in));
    // Rows 5..10 into a buffer of their own, as an output strip is.
    ImageSpec stripSpec(24, 5, 3, TypeDesc::UINT8);
    stripSpec.y = 5;
    std::vector<uint8_t> rows(stripSpec.image_bytes());
    ImageBuf strip(stripSpec, rows.data());
    ASSERT_TRUE(quantize(strip, in));
    EXPECT_EQ(std::memcmp(rows.data(), whole.pixeladdr(0, 5), rows.size()), 0);
    // Too few source channels, or a float destination: an error, not a crash.
    ImageBuf wide(ImageSpec(24, 20, 4, TypeDesc::UINT8)),
        floats(ImageSpec(4, 4, 3, TypeDesc::FLOAT));
    EXPECT_FALSE(quantize(wide, in));
    EXPECT_FALSE(quantize(floats, in));
    EXPECT_TRUE(floats.has_error());
}

TEST(Adaptation, StepChangeFollowsTheSeedsFormula) {
    // adapted += (L − adapted)(1 − 0.98^(30 dt)) at 24 fps: each frame closes
    // 1 − 0.98^1.25 = 2.4937 % of the gap.
    const std::vector<double> L = {2.0, 2.0, 10.0, 10.0, 10.0, 1.0};
    const std::vector<double> adapted = adaptLuminance(L);
    const double k = 1.0 - std::pow(0.98, 30.0 / 24.0);
    EXPECT_NEAR(k, 0.024937, 1e-6);
    double a = 2.0;
    for (size_t i = 0; i < L.size(); ++i) {
        if (i > 0) a += (L[i] - a) * k;
        EXPECT_NEAR(adapted[i], a, 1e-12) << i;
    }
    EXPECT_EQ(adapted[0], 2.0); // starts adapted to the first frame
}
