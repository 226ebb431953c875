// dhdr-gbuffer over an animation at its edges (issue 48): frame times at extreme --fps, which
// animation an index names, a frame either side without a camera, STEP keys stored as float
// times, and --lights-out's pattern; each as a user runs the tool.
#include "animation_writer.h"
#include "tool_test.h"

#include <cmath>
#include <cstdio>

using namespace dhdr::test;

namespace {

class AnimationEdges : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    static float value(const ImageBuf& img, const char* name, int x, int y) {
        const int c = img.spec().channelindex(name);
        EXPECT_GE(c, 0) << name;
        return c < 0 ? NAN : static_cast<const float*>(img.pixeladdr(x, y))[c];
    }

    static std::string frameName(const char* stem, int f) {
        char name[64];
        std::snprintf(name, sizeof name, "%s.%04d.exr", stem, f);
        return name;
    }
};

} // namespace

// --fps is a decimal number, checked as the float it would be, and every time it poses the
// scene at lies in --time's range: 0x18, 1e-50 (0 as a float) and 1e-45 (frame 1 at 1e45 s)
// are usage errors before anything is written; 0.001 and 1e6 render.
TEST_F(AnimationEdges, FpsIsDecimalAndItsFrameTimesInRange) {
    nlohmann::json doc = squareAndCamera();
    addChannel(doc, 0, 0, "translation", {0.0f, 2.0f}, {-1, 0, 0, 1, 0, 0});
    writeJson(path("fps.gltf"), doc);
    for (const char* fps : {"0x18", "1e-50", "1e-45", "1e-300"}) {
        const Result r = run("dhdr-gbuffer " + path("fps.gltf") + " --size 16x16 --fps " + fps +
                             " --frames 0-1 -o " + path("bad.####.exr"));
        EXPECT_EQ(r.status, 2) << fps << ": " << r.err;
        EXPECT_NE(r.err.find("--fps"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path(frameName("bad", 0)))) << fps;
        EXPECT_FALSE(fs::exists(path(frameName("bad", 1)))) << fps;
    }
    for (const char* fps : {"0.001", "1e6", "1000000"}) {
        const Result r = run("dhdr-gbuffer " + path("fps.gltf") + " --size 16x16 --fps " + fps +
                             " --frames 0-1 -o " + path("good.####.exr"));
        EXPECT_EQ(r.status, 0) << fps << ": " << r.err;
        for (int f = 0; f <= 1; ++f) {
            EXPECT_TRUE(fs::exists(path(frameName("good", f)))) << fps << " " << f;
            fs::remove(path(frameName("good", f)));
        }
    }
}

// --animation 0 is index 0, even when another animation is named "0"; a name that is no index
// is still found by its name.
TEST_F(AnimationEdges, AnIndexNamesByPositionBeforeAName) {
    nlohmann::json doc = squareAndCamera();
    addChannel(doc, 0, 0, "translation", {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0});
    addChannel(doc, 1, 0, "translation", {0.0f, 1.0f}, {0, 0, 0, 0, 1, 0});
    addChannel(doc, 2, 0, "translation", {0.0f, 1.0f}, {0, 0, 0, -1, 0, 0});
    doc["animations"][1]["name"] = "0";
    doc["animations"][2]["name"] = "7";
    writeJson(path("named.gltf"), doc);
    // At 1 s the square's centre is at (1, 0) under animation 0, (0, 1) under the one named
    // "0", (−1, 0) under the one named "7": pixel (32 ± 16, 32) or (32, 48).
    const std::pair<const char*, float> cases[] = {{"0", 1.0f}, {"7", -1.0f}};
    for (const auto& [choice, x] : cases) {
        const Result r =
            run("dhdr-gbuffer " + path("named.gltf") + " --size 64x64 --time 1 --animation " +
                choice + " -o " + path("named.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
        const ImageBuf g = read("named.exr");
        const int px = 32 + int(16 * x);
        EXPECT_GT(value(g, "A", px, 32), 0.0f) << choice;
        EXPECT_NEAR(value(g, "P.X", px, 32), x + 1.0 / 32, 1e-5) << choice;
        EXPECT_NEAR(value(g, "P.Y", px, 32), 0.0, 0.05) << choice;
    }
}

// The camera cannot be rendered from at frame 12 (its node scaled by 0): frame 12 fails, and
// frames 11 and 13 are written with the half of their motion that needs frame 12 at 0 and a
// warning, as for a point behind the camera; their other half is the square's motion.
TEST_F(AnimationEdges, AFrameWithoutACameraZeroesItsNeighboursHalf) {
    nlohmann::json doc = squareAndCamera();
    addChannel(doc, 0, 0, "translation", {0.0f, 2.0f}, {-3, 0, 0, 9, 0, 0});
    const float t11 = 11.0f / 24, t12 = 12.0f / 24, t13 = 13.0f / 24;
    addChannel(doc, 0, 1, "scale", {t11, t12, t13}, {1, 1, 1, 0, 0, 0, 1, 1, 1}, "STEP");
    writeJson(path("blink.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("blink.gltf") + " --size 64x64 --frames 10-14 -o " +
                         path("blink.####.exr"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("1 of 5 frames failed"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("that half of the motion layer is 0"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path(frameName("blink", 12))));
    ASSERT_TRUE(fs::exists(path(frameName("blink", 11)))) << r.err;
    ASSERT_TRUE(fs::exists(path(frameName("blink", 13)))) << r.err;
    // The square moves +x 4 pixels a frame: its centre at −3 + f / 4 units, 16 pixels a unit.
    const ImageBuf f11 = read(frameName("blink", 11)), f13 = read(frameName("blink", 13));
    const int x11 = 4 * 11 - 16, x13 = 4 * 13 - 16;
    ASSERT_GT(value(f11, "A", x11, 32), 0.0f);
    ASSERT_GT(value(f13, "A", x13, 32), 0.0f);
    EXPECT_NEAR(value(f11, "motion.X", x11, 32), -4.0f, 1e-4);
    EXPECT_EQ(value(f11, "motion.Z", x11, 32), 0.0f);
    EXPECT_EQ(value(f13, "motion.X", x13, 32), 0.0f);
    EXPECT_NEAR(value(f13, "motion.Z", x13, 32), -4.0f, 1e-4);
}

// STEP keys stored as float32 N / 24, as Blender exports them: the square steps 1 unit (16
// pixels) at frame 12 (key 0.5 s) and again at frame 13 (whose float key is later than the
// double 13 / 24). Each jump shows on its own frame, once: frame 14's previous half is 0.
TEST_F(AnimationEdges, StepKeysStoredAsFloatsJumpOnTheirFrames) {
    nlohmann::json doc = squareAndCamera();
    std::vector<float> times, values;
    for (int n = 0; n <= 24; ++n) {
        times.push_back(float(double(n) / 24.0));
        const float x = n < 12 ? -1.5f : n < 13 ? -0.5f : 0.5f;
        values.insert(values.end(), {x, 0.0f, 0.0f});
    }
    addChannel(doc, 0, 0, "translation", times, values, "STEP");
    writeJson(path("blender_step.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("blender_step.gltf") +
                         " --size 64x64 --frames 11-14 -o " + path("bstep.####.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    // Frame: the square's centre pixel, motion X (previous − now) and Z (now − next).
    const struct {
        int frame, x;
        float motionX, motionZ;
    } expected[] = {{11, 8, 0.0f, -16.0f},
                    {12, 24, -16.0f, -16.0f},
                    {13, 40, -16.0f, 0.0f},
                    {14, 40, 0.0f, 0.0f}};
    for (const auto& e : expected) {
        const ImageBuf g = read(frameName("bstep", e.frame));
        EXPECT_NEAR(value(g, "P.X", e.x, 32), (e.x - 32) / 16.0 + 1.0 / 32, 1e-5) << e.frame;
        EXPECT_NEAR(value(g, "motion.X", e.x, 32), e.motionX, 1e-4) << e.frame;
        EXPECT_NEAR(value(g, "motion.Z", e.x, 32), e.motionZ, 1e-4) << e.frame;
    }
}

// One frame has one lights file: a frame pattern in --lights-out without one in -o is a usage
// error, before anything is written.
TEST_F(AnimationEdges, ALightsPatternNeedsAnOutputPattern) {
    writeJson(path("lamp.gltf"), squareAndCamera());
    for (const std::string extra : {"", " --frame 12"}) {
        const Result r = run("dhdr-gbuffer " + path("lamp.gltf") + " --size 16x16" + extra +
                             " --lights-out " + path("l.####.json") + " -o " + path("one.exr"));
        EXPECT_EQ(r.status, 2) << r.err;
        EXPECT_NE(r.err.find("--lights-out"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("one.exr")));
        EXPECT_FALSE(fs::exists(path("l.0000.json")));
        EXPECT_FALSE(fs::exists(path("l.0012.json")));
    }
}

// --frame-all over an animation frames its whole span once: the camera is the same at every
// frame (it does not breathe with the pose), so the square that stands still has a motion of
// exactly 0 while the other slides, and both stay in view at either end of the slide.
TEST_F(AnimationEdges, FrameAllFramesTheWholeAnimationOnce) {
    nlohmann::json doc = squareAndCamera();
    doc["nodes"].push_back({{"name", "still"}, {"mesh", 0}, {"translation", {0.0, 1.5, 0.0}}});
    doc["scenes"][0]["nodes"] = {0, 1, 2};
    addChannel(doc, 0, 0, "translation", {0.0f, 1.0f}, {-2, 0, 0, 2, 0, 0});
    writeJson(path("span.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("span.gltf") +
                         " --size 64x64 --frame-all --frames 0-24 -o " + path("span.####.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    std::vector<float> first;
    for (const int f : {0, 5, 12, 24}) {
        const ImageBuf g = read(frameName("span", f));
        const OIIO::ParamValue* w = g.spec().find_attribute("worldToCamera");
        ASSERT_TRUE(w) << f;
        const auto* m = static_cast<const float*>(w->data());
        if (first.empty()) first.assign(m, m + 16);
        for (int i = 0; i < 16; ++i)
            EXPECT_EQ(m[i], first[size_t(i)]) << "frame " << f << " element " << i;
        long long still = 0, moving = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                if (!(value(g, "A", x, y) > 0.0f)) continue;
                const bool isStill = value(g, "P.Y", x, y) > 0.9f;
                (isStill ? still : moving) += 1;
                if (isStill)
                    for (const char* c : {"motion.X", "motion.Y", "motion.Z", "motion.W"})
                        ASSERT_EQ(value(g, c, x, y), 0.0f) << f << " " << c << " " << x << "," << y;
            }
        EXPECT_GT(still, 0) << f;
        EXPECT_GT(moving, 0) << f;
    }
}
