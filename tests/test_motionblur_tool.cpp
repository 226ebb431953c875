// dhdr-motionblur run as a user runs it: the library's whole-frame result from the streamed
// tool, the input itself without motion, Blender's Vector pass, and bad input.
#include "tool_test.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <dhdr/tonemap/motion_blur.h>

using namespace dhdr;
using namespace dhdr::test;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

class MotionBlurTool : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    // A W × H HDR frame (R, G, B, A) and a G-buffer with Z and the motion in `names` (4) —
    // rings of different depths moving in different directions over a static background.
    static void write(const std::string& hdr, const std::string& gbuf, int W, int H, float speed,
                      const std::vector<std::string>& names, const std::string& depthName) {
        ImageSpec cs(W, H, 4, TypeDesc::FLOAT);
        cs.attribute("dhdr:test", "kept");
        ImageBuf colour(cs);
        ImageSpec gs(W, H, 5, TypeDesc::FLOAT);
        gs.channelnames = {depthName, names[0], names[1], names[2], names[3]};
        ImageBuf g(gs);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const float dx = float(x) - 0.5f * float(W), dy = float(y) - 0.5f * float(H);
                const int ring = int(std::sqrt(dx * dx + dy * dy) / 12.0f);
                const bool moving = ring % 2 == 1;
                const float c = moving ? 4.0f + float(ring) : 0.2f + 0.01f * float(x % 7);
                const float rgba[4] = {c, 0.7f * c, 0.4f * c, 1.0f};
                const float u = moving ? speed * float(ring % 3 - 1 + (ring == 1)) : 0.0f;
                const float v = moving ? 0.5f * speed : 0.0f;
                const float px[5] = {moving ? 2.0f + float(ring) : 50.0f, -u, -v, -u, -v};
                colour.setpixel(x, y, rgba);
                g.setpixel(x, y, px);
            }
        ASSERT_TRUE(colour.write(hdr));
        ASSERT_TRUE(g.write(gbuf));
    }
};

} // namespace

TEST_F(MotionBlurTool, TheStreamedToolGivesTheLibrarysWholeFrame) {
    write(path("a.exr"), path("a.gbuf.exr"), 160, 300, 9.0f,
          {"motion.X", "motion.Y", "motion.Z", "motion.W"}, "Z");
    const Result r = run("dhdr-motionblur " + path("a.exr") + " --gbuffer " + path("a.gbuf.exr") +
                         " --shutter 1 --max-blur 16 -o " + path("a.mb.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    ImageBuf colour(path("a.exr")), g(path("a.gbuf.exr")), out(path("a.mb.exr"));
    ASSERT_TRUE(colour.read(0, 0, true, TypeDesc::FLOAT) && g.read(0, 0, true, TypeDesc::FLOAT));
    const int m[4] = {1, 2, 3, 4}, z[1] = {0};
    ImageBuf motion = OIIO::ImageBufAlgo::channels(g, 4, m);
    ImageBuf depth = OIIO::ImageBufAlgo::channels(g, 1, z);
    MotionBlurParams params;
    params.shutter = 1.0f;
    params.maxBlur = 16;
    ImageBuf expected;
    ASSERT_TRUE(motionBlur(expected, colour, motion, depth, params)) << expected.geterror();
    const auto cmp = OIIO::ImageBufAlgo::compare(out, expected, 0.0f, 0.0f);
    EXPECT_EQ(cmp.nfail, 0u) << "max error " << cmp.maxerror << " at " << cmp.maxx << ","
                             << cmp.maxy;
    // Blurred where the rings move, the metadata kept.
    EXPECT_GT(OIIO::ImageBufAlgo::compare(out, colour, 1e-3f, 1e-3f).nfail, 1000u);
    EXPECT_EQ(out.spec().get_string_attribute("dhdr:test"), "kept");
}

TEST_F(MotionBlurTool, WithoutMotionTheOutputIsTheInput) {
    write(path("s.exr"), path("s.gbuf.exr"), 64, 90, 0.0f,
          {"motion.X", "motion.Y", "motion.Z", "motion.W"}, "Z");
    const Result r = run("dhdr-motionblur " + path("s.exr") + " --gbuffer " + path("s.gbuf.exr") +
                         " -o " + path("s.mb.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const auto cmp =
        OIIO::ImageBufAlgo::compare(ImageBuf(path("s.mb.exr")), ImageBuf(path("s.exr")), 0, 0);
    EXPECT_EQ(cmp.nfail, 0u);
    EXPECT_EQ(cmp.maxerror, 0.0);
}

// Blender's Vector and Depth passes name the channels; the same blur as dhdr's names.
TEST_F(MotionBlurTool, BlendersVectorPassWorksAsDhdrsMotion) {
    write(path("b.exr"), path("b.gbuf.exr"), 96, 96, 6.0f,
          {"motion.X", "motion.Y", "motion.Z", "motion.W"}, "Z");
    write(path("b.exr"), path("blender.exr"), 96, 96, 6.0f,
          {"ViewLayer.Vector.X", "ViewLayer.Vector.Y", "ViewLayer.Vector.Z", "ViewLayer.Vector.W"},
          "ViewLayer.Depth.Z");
    ASSERT_EQ(run("dhdr-motionblur " + path("b.exr") + " --gbuffer " + path("b.gbuf.exr") + " -o " +
                  path("b1.exr"))
                  .status,
              0);
    const Result r = run("dhdr-motionblur " + path("b.exr") + " --gbuffer " + path("blender.exr") +
                         " -o " + path("b2.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(
        OIIO::ImageBufAlgo::compare(ImageBuf(path("b1.exr")), ImageBuf(path("b2.exr")), 0, 0).nfail,
        0u);
}

TEST_F(MotionBlurTool, BadInputIsAClearErrorAndWritesNothing) {
    write(path("c.exr"), path("c.gbuf.exr"), 32, 32, 4.0f,
          {"motion.X", "motion.Y", "motion.Z", "motion.W"}, "Z");
    // A G-buffer without motion (the colour file itself): which file, what is missing.
    Result r = run("dhdr-motionblur " + path("c.exr") + " --gbuffer " + path("c.exr") + " -o " +
                   path("x.exr"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(path("c.exr") + ": no motion channels"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
    // Sizes that disagree.
    write(path("d.exr"), path("d.gbuf.exr"), 40, 32, 4.0f,
          {"motion.X", "motion.Y", "motion.Z", "motion.W"}, "Z");
    r = run("dhdr-motionblur " + path("c.exr") + " --gbuffer " + path("d.gbuf.exr") + " -o " +
            path("x.exr"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("is 40x32 but"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
    // Out-of-range options are usage errors.
    r = run("dhdr-motionblur " + path("c.exr") + " --gbuffer " + path("c.gbuf.exr") +
            " --shutter 3 -o " + path("x.exr"));
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--shutter"), std::string::npos) << r.err;
    // NaN motion is no motion: the output is finite.
    ImageBuf g(path("c.gbuf.exr"));
    ASSERT_TRUE(g.read(0, 0, true, TypeDesc::FLOAT));
    const float nan = std::nanf("");
    for (int y = 0; y < 32; y += 3)
        g.setpixel(5, y, std::vector<float>{1.0f, nan, nan, nan, nan}.data());
    ASSERT_TRUE(g.write(path("nan.gbuf.exr")));
    r = run("dhdr-motionblur " + path("c.exr") + " --gbuffer " + path("nan.gbuf.exr") + " -o " +
            path("n.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const auto stats = OIIO::ImageBufAlgo::computePixelStats(ImageBuf(path("n.exr")));
    for (size_t c = 0; c < 4; ++c)
        EXPECT_EQ(stats.nancount[c] + stats.infcount[c], 0u);
}
