// dhdr-light with the scene, run as a user runs it: shadows, emissive lights, AO, and the
// errors of its options.
#include "blender_passes.h"
#include "tool_test.h"

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <fstream>

using namespace dhdr::test;

namespace {

const std::string kCornell = kTestdata + "/cornell_box.gltf";
const std::string kLights = kTestdata + "/cornell_box.lights.json";
const std::string kFill = kTestdata + "/cornell_box.fill.lights.json";

class LightTools : public ToolTest {
protected:
    static void SetUpTestSuite() {
        makeScratch();
        sharedInputs([] {
            ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 96x96 -o " + path("g.exr")).status,
                      0);
        });
    }

    // Pixels of two images identical, channel by channel.
    static bool samePixels(const ImageBuf& a, const ImageBuf& b) {
        if (a.nchannels() != b.nchannels() || a.spec().image_pixels() != b.spec().image_pixels())
            return false;
        const auto* p = static_cast<const float*>(a.localpixels());
        const auto* q = static_cast<const float*>(b.localpixels());
        return std::equal(p, p + a.spec().image_pixels() * size_t(a.nchannels()), q);
    }
};

} // namespace

TEST_F(LightTools, SceneThatDoesNotLoadFailsNamingIt) {
    const Result r = run("dhdr-light " + path("g.exr") + " --scene " + path("nope.gltf") + " -o " +
                         path("x.exr"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("nope.gltf"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
    EXPECT_TRUE(noTemporaries());
}

TEST_F(LightTools, OptionsThatNeedTheSceneAreUsageErrors) {
    for (const char* option :
         {"--ao rt", "--no-shadows", "--emissive-lights on", "--env-samples 4"}) {
        const Result r = run("dhdr-light " + path("g.exr") + " --lights " + kLights + " " + option +
                             " -o " + path("x.exr"));
        EXPECT_EQ(r.status, 2) << option;
        EXPECT_NE(r.err.find("--scene"), std::string::npos) << r.err;
    }
    const Result none = run("dhdr-light " + path("g.exr") + " -o " + path("x.exr"));
    EXPECT_EQ(none.status, 2);
    EXPECT_NE(none.err.find("--lights"), std::string::npos) << none.err;
    const Result bad = run("dhdr-light " + path("g.exr") + " --scene " + kCornell +
                           " --ao maybe -o " + path("x.exr"));
    EXPECT_EQ(bad.status, 2);
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

TEST_F(LightTools, WithoutSceneNothingIsShadowedAndVerboseSaysSo) {
    const Result r = run("dhdr-light " + path("g.exr") + " --lights " + kLights + " -v -o " +
                         path("plain.exr") + " --type float");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("no --scene"), std::string::npos) << r.err;
    // --no-shadows with the scene's emissive lights off is that same unshadowed image.
    const Result s = run("dhdr-light --gi direct " + path("g.exr") + " --lights " + kLights +
                         " --scene " + kCornell + " --no-shadows --emissive-lights off -o " +
                         path("noshadows.exr") + " --type float");
    ASSERT_EQ(s.status, 0) << s.err;
    EXPECT_TRUE(samePixels(read("plain.exr"), read("noshadows.exr")));
    // Shadows darken some pixels and brighten none.
    ASSERT_EQ(run("dhdr-light --gi direct " + path("g.exr") + " --lights " + kLights + " --scene " +
                  kCornell + " --emissive-lights off --type float -o " + path("shadowed.exr"))
                  .status,
              0);
    const ImageBuf plain = read("plain.exr"), shadowed = read("shadowed.exr");
    int darker = 0;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x)
            for (int c = 0; c < 3; ++c) {
                const float a = plain.getchannel(x, y, 0, c), b = shadowed.getchannel(x, y, 0, c);
                ASSERT_LE(b, a);
                darker += b < a;
            }
    EXPECT_GT(darker, 500);
}

TEST_F(LightTools, TheScenesOwnLightsAndGlowingPanelLightIt) {
    // No --lights: the scene's punctual lights plus its emissive panel.
    const Result r = run("dhdr-light --gi direct " + path("g.exr") + " --scene " + kCornell +
                         " -v --type float -o " + path("own.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("1 emissive mesh as area lights"), std::string::npos) << r.err;
    // The panel alone (its punctual lights replaced by an empty lights file) still lights the
    // box: a Cornell box with no hand-written lights.
    { std::ofstream(path("none.json")) << "{\"lights\": []}\n"; }
    ASSERT_EQ(run("dhdr-light --gi direct " + path("g.exr") + " --scene " + kCornell +
                  " --lights " + path("none.json") + " --type float -o " + path("panel.exr"))
                  .status,
              0);
    const OIIO::ImageBufAlgo::PixelStats lit =
        OIIO::ImageBufAlgo::computePixelStats(read("panel.exr"));
    ASSERT_FALSE(lit.avg.empty());
    const Result off =
        run("dhdr-light --gi direct " + path("g.exr") + " --scene " + kCornell + " --lights " +
            path("none.json") + " --emissive-lights off --type float -o " + path("dark.exr"));
    ASSERT_EQ(off.status, 0);
    const OIIO::ImageBufAlgo::PixelStats dark =
        OIIO::ImageBufAlgo::computePixelStats(read("dark.exr"));
    ASSERT_FALSE(dark.avg.empty());
    // Off, only the panel's own pixels glow; on, the walls, floor and blocks are lit too.
    EXPECT_GT(lit.avg[0], 1.3 * dark.avg[0]);
}

TEST_F(LightTools, ResultsDoNotDependOnTheThreadCount) {
    for (const int threads : {1, 2})
        ASSERT_EQ(run("dhdr-light " + path("g.exr") + " --scene " + kCornell + " --lights " +
                      kLights + " --lights " + kFill +
                      " --ao rt --aovs --shadow-samples 8 --type float --threads " +
                      std::to_string(threads) + " -o " +
                      path("t" + std::to_string(threads) + ".exr"))
                      .status,
                  0);
    const ImageBuf a = read("t1.exr"), b = read("t2.exr");
    EXPECT_GE(a.spec().channelindex("AO"), 4);
    EXPECT_TRUE(samePixels(a, b));
}

TEST_F(LightTools, WarnsWhenTheSceneIsAnotherFile) {
    const Result same = run("dhdr-light --gi direct " + path("g.exr") + " --scene " + kCornell +
                            " -o " + path("same.exr"));
    ASSERT_EQ(same.status, 0) << same.err;
    EXPECT_EQ(same.err.find("another scene"), std::string::npos) << same.err;
    // The same scene with one byte more is another file.
    fs::copy_file(kCornell, path("edited.gltf"), fs::copy_options::overwrite_existing);
    std::ofstream(path("edited.gltf"), std::ios::app) << "\n";
    const Result other = run("dhdr-light --gi direct " + path("g.exr") + " --scene " +
                             path("edited.gltf") + " -o " + path("other.exr"));
    ASSERT_EQ(other.status, 0) << other.err;
    EXPECT_NE(other.err.find("another scene"), std::string::npos) << other.err;
}

TEST_F(LightTools, ScreenSpaceAOWorksWithoutTheScene) {
    const Result r =
        run("dhdr-light " + path("g.exr") + " --lights " + kLights + " --lights " + kFill +
            " --ao ssao --ao-distance 0.1 --aovs --type float -o " + path("ssao.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf img = read("ssao.exr");
    const int ao = img.spec().channelindex("AO");
    ASSERT_GE(ao, 4);
    const OIIO::ImageBufAlgo::PixelStats stats = OIIO::ImageBufAlgo::computePixelStats(img);
    ASSERT_FALSE(stats.min.empty());
    EXPECT_GE(stats.min[ao], 0.0f);
    EXPECT_LE(stats.max[ao], 1.0f);
    EXPECT_LT(stats.avg[ao], 0.99); // the box's corners are occluded
    for (int c : {0, 1, 2, 3, ao}) {
        EXPECT_TRUE(std::isfinite(stats.min[c]) && std::isfinite(stats.max[c])) << c;
        EXPECT_EQ(stats.nancount[c] + stats.infcount[c], 0u) << c;
    }
}

namespace {

// A 2:1 sky written with OpenImageIO: brighter up, warmer towards +X.
void writeSky(const std::string& path, int width) {
    OIIO::ImageBuf sky(OIIO::ImageSpec(width, width / 2, 3, OIIO::TypeDesc::FLOAT));
    for (int y = 0; y < width / 2; ++y)
        for (int x = 0; x < width; ++x) {
            const float up = std::cos(float(M_PI) * (y + 0.5f) / float(width / 2));
            const float v[3] = {0.6f + 0.3f * up + 0.2f * float(x) / float(width),
                                0.7f + 0.35f * up, 0.9f + 0.6f * up};
            sky.setpixel(x, y, v);
        }
    ASSERT_TRUE(sky.write(path));
}

} // namespace

TEST_F(LightTools, EnvironmentLightRawOrBakedGivesTheSameFrame) {
    writeSky(path("sky.exr"), 256);
    ASSERT_EQ(run("dhdr-gbuffer " + kCornell +
                  " --lookat 0.28,0.4,-1.6,0.28,0.27,0.28 --fov 50 --size 80x60 -o " +
                  path("outside.exr"))
                  .status,
              0);
    const Result bake = run("dhdr-ibl " + path("sky.exr") + " -o " + path("sky.ibl.exr") + " -v");
    ASSERT_EQ(bake.status, 0) << bake.err;
    EXPECT_NE(bake.err.find("bake"), std::string::npos);
    {
        std::ofstream(path("raw.json"))
            << R"({"lights": [{"type": "environment", "image": "sky.exr", "rotation": 30}]})";
        std::ofstream(path("baked.json"))
            << R"({"lights": [{"type": "environment", "image": "sky.ibl.exr", "rotation": 30}]})";
    }
    const Result raw = run("dhdr-light " + path("outside.exr") + " --lights " + path("raw.json") +
                           " --background env --type float -v -o " + path("env_raw.exr"));
    ASSERT_EQ(raw.status, 0) << raw.err;
    EXPECT_NE(raw.err.find("environment images in"), std::string::npos) << raw.err;
    ASSERT_EQ(run("dhdr-light " + path("outside.exr") + " --lights " + path("baked.json") +
                  " --background env --type float -o " + path("env_baked.exr"))
                  .status,
              0);
    const ImageBuf a = read("env_raw.exr"), b = read("env_baked.exr");
    EXPECT_TRUE(samePixels(a, b));
    // The background is the sky, opaque; the box is lit by it.
    const ImageBuf g = read("outside.exr");
    int background = 0;
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x) {
            const bool covered = g.getchannel(x, y, 0, g.spec().channelindex("A")) > 0.0f;
            EXPECT_EQ(a.getchannel(x, y, 0, 3), 1.0f);
            EXPECT_GT(a.getchannel(x, y, 0, 2), 0.0f);
            background += !covered;
        }
    EXPECT_GT(background, 500);
}

TEST_F(LightTools, EnvironmentThatCannotBeReadIsAnErrorNamingIt) {
    std::ofstream(path("gone.json"))
        << R"({"lights": [{"type": "environment", "image": "gone.hdr"}]})";
    const Result r = run("dhdr-light " + path("g.exr") + " --lights " + path("gone.json") + " -o " +
                         path("x.exr"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("gone.json"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("gone.hdr"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
    const Result ibl = run("dhdr-ibl " + path("gone.hdr") + " -o " + path("x.ibl.exr"));
    EXPECT_EQ(ibl.status, 1);
    EXPECT_NE(ibl.err.find("gone.hdr"), std::string::npos) << ibl.err;
    EXPECT_FALSE(fs::exists(path("x.ibl.exr")));
    EXPECT_TRUE(noTemporaries());
}

TEST_F(LightTools, GroundPlaneCatchesShadowsAndPlatesComposite) {
    writeSky(path("sky2.exr"), 128);
    std::ofstream(path("sky2.json"))
        << R"({"lights": [{"type": "environment", "image": "sky2.exr"}]})";
    const std::string spheres = kTestdata + "/spheres.gltf";
    const Result g =
        run("dhdr-gbuffer " + spheres + " --size 64x36 --ground-plane 0.001 -o " + path("sp.exr"));
    ASSERT_EQ(g.status, 0) << g.err;
    const ImageBuf gbuf = read("sp.exr");
    EXPECT_FLOAT_EQ(gbuf.spec().get_float_attribute("dhdr:groundPlaneY"), 0.001f);
    const int catcher = gbuf.spec().get_int_attribute("dhdr:shadowCatcher");
    EXPECT_GT(catcher, 0);
    // Without a number the plane goes to the scene's lowest point, 0 for the spheres.
    ASSERT_EQ(run("dhdr-gbuffer " + spheres + " --size 64x36 --ground-plane -o " + path("sp0.exr"))
                  .status,
              0);
    EXPECT_NEAR(read("sp0.exr").spec().get_float_attribute("dhdr:groundPlaneY"), 0.0f, 1e-6f);

    const Result lit =
        run("dhdr-light " + path("sp.exr") + " --scene " + spheres + " --lights " +
            path("sky2.json") + " --env-samples 4 --type float -o " + path("sp_lit.exr"));
    ASSERT_EQ(lit.status, 0) << lit.err;
    const ImageBuf l = read("sp_lit.exr");
    int catcherPixels = 0;
    for (int y = 0; y < 36; ++y)
        for (int x = 0; x < 64; ++x) {
            const float a = l.getchannel(x, y, 0, 3);
            ASSERT_GE(a, 0.0f);
            ASSERT_LE(a, 1.0f);
            if (gbuf.getchannel(x, y, 0, gbuf.spec().channelindex("A")) > 0.0f &&
                l.getchannel(x, y, 0, 0) == 0.0f && l.getchannel(x, y, 0, 1) == 0.0f)
                ++catcherPixels;
        }
    EXPECT_GT(catcherPixels, 300);
    // Over the environment: opaque everywhere.
    ASSERT_EQ(run("dhdr-light " + path("sp.exr") + " --lights " + path("sky2.json") +
                  " --plate env --type float -o " + path("sp_env.exr"))
                  .status,
              0);
    const OIIO::ImageBufAlgo::PixelStats stats =
        OIIO::ImageBufAlgo::computePixelStats(read("sp_env.exr"));
    ASSERT_FALSE(stats.min.empty());
    EXPECT_EQ(stats.min[3], 1.0f);
    // A plate of another size, or --plate env without an environment: errors, no output.
    OIIO::ImageBuf small(OIIO::ImageSpec(10, 10, 3, OIIO::TypeDesc::FLOAT));
    ASSERT_TRUE(small.write(path("small.exr")));
    const Result wrong = run("dhdr-light " + path("sp.exr") + " --lights " + path("sky2.json") +
                             " --plate " + path("small.exr") + " -o " + path("bad.exr"));
    EXPECT_EQ(wrong.status, 1);
    EXPECT_NE(wrong.err.find("10x10"), std::string::npos) << wrong.err;
    const Result noEnv = run("dhdr-light " + path("sp.exr") + " --lights " + kFill +
                             " --plate env -o " + path("bad.exr"));
    EXPECT_EQ(noEnv.status, 1);
    EXPECT_FALSE(fs::exists(path("bad.exr")));
}

namespace {

const std::string kGlass = kTestdata + "/cornell_glass.gltf";

bool isDeep(const std::string& file) {
    auto in = OIIO::ImageInput::open(file);
    return in && in->spec().deep;
}

} // namespace

TEST_F(LightTools, GBufferIsDeepWhereSurfacesAreTransparent) {
    // A scene with glass: deep by default; --flat: today's first-hit file; an opaque scene:
    // flat unless --deep; --deep and --flat together: a usage error.
    ASSERT_EQ(run("dhdr-gbuffer " + kGlass + " --size 64x64 -o " + path("glass.exr")).status, 0);
    EXPECT_TRUE(isDeep(path("glass.exr")));
    ASSERT_EQ(
        run("dhdr-gbuffer " + kGlass + " --size 64x64 --flat -o " + path("glassflat.exr")).status,
        0);
    EXPECT_FALSE(isDeep(path("glassflat.exr")));
    EXPECT_FALSE(isDeep(path("g.exr")));
    ASSERT_EQ(
        run("dhdr-gbuffer " + kCornell + " --size 64x64 --deep -o " + path("opaque.exr")).status,
        0);
    EXPECT_TRUE(isDeep(path("opaque.exr")));
    const Result both = run("dhdr-gbuffer " + kGlass + " --deep --flat -o " + path("both.exr"));
    EXPECT_EQ(both.status, 2);
    EXPECT_FALSE(fs::exists(path("both.exr")));
    // Every pixel of the opaque scene's deep file has one sample; the glass scene's pane
    // pixels two.
    OIIO::ImageBuf opaque(path("opaque.exr")), glass(path("glass.exr"));
    ASSERT_TRUE(opaque.read(0, 0, true) && glass.read(0, 0, true));
    int maxOpaque = 0, maxGlass = 0;
    for (int64_t p = 0; p < 64 * 64; ++p) {
        maxOpaque = std::max(maxOpaque, opaque.deepdata()->samples(p));
        maxGlass = std::max(maxGlass, glass.deepdata()->samples(p));
    }
    EXPECT_EQ(maxOpaque, 1);
    EXPECT_EQ(maxGlass, 2);
    // --max-layers 1 keeps only the opaque surface of each pixel.
    ASSERT_EQ(
        run("dhdr-gbuffer " + kGlass + " --size 64x64 --deep --max-layers 1 -o " + path("one.exr"))
            .status,
        0);
    OIIO::ImageBuf one(path("one.exr"));
    ASSERT_TRUE(one.read(0, 0, true));
    const int a = one.spec().channelindex("A");
    for (int64_t p = 0; p < 64 * 64; ++p) {
        ASSERT_LE(one.deepdata()->samples(p), 1);
        if (one.deepdata()->samples(p) == 1) {
            EXPECT_EQ(one.deepdata()->deep_value(p, a, 0), 1.0f);
        }
    }
}

TEST_F(LightTools, DeepLightingFlattensToTheFlatOutput) {
    // dhdr-light on the deep G-buffer: its flat output equals OpenImageIO's flatten of its
    // --deep-out file (tidy: sorted, premultiplied), and the pane tints what is behind it.
    // 300 rows: dhdr-light reads, lights and writes the deep G-buffer in three bands.
    ASSERT_EQ(run("dhdr-gbuffer " + kGlass + " --size 80x300 -o " + path("dg.exr")).status, 0);
    const Result r = run("dhdr-light --gi direct " + path("dg.exr") + " --scene " + kGlass +
                         " --lights " + kLights + " --type float --deep-out " + path("ddeep.exr") +
                         " -o " + path("dflat.exr") + " -v");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("deep:"), std::string::npos) << r.err;
    ASSERT_TRUE(isDeep(path("ddeep.exr")));
    OIIO::ImageBuf deep(path("ddeep.exr"));
    ASSERT_TRUE(deep.read(0, 0, true));
    const OIIO::ImageBuf flattened = OIIO::ImageBufAlgo::flatten(deep);
    ASSERT_FALSE(flattened.has_error()) << flattened.geterror();
    const ImageBuf flat = read("dflat.exr");
    ASSERT_TRUE(allFinite(flat));
    int compared = 0;
    for (int y = 0; y < 300; ++y)
        for (int x = 0; x < 80; ++x)
            for (int c = 0; c < 4; ++c) {
                const float a = flattened.getchannel(
                    x, y, 0, flattened.spec().channelindex(std::string(1, "RGBA"[c])));
                const float b = flat.getchannel(x, y, 0, c);
                EXPECT_NEAR(a, b, 1e-5f + 1e-5f * std::abs(b)) << x << "," << y << " " << c;
                ++compared;
            }
    EXPECT_EQ(compared, 80 * 300 * 4);
    // --deep-out needs a deep G-buffer; SSAO a flat one.
    const Result flatIn = run("dhdr-light " + path("g.exr") + " --lights " + kLights +
                              " --deep-out " + path("x_deep.exr") + " -o " + path("x.exr"));
    EXPECT_EQ(flatIn.status, 1);
    EXPECT_NE(flatIn.err.find("deep"), std::string::npos) << flatIn.err;
    const Result ssao = run("dhdr-light " + path("dg.exr") + " --lights " + kLights +
                            " --ao ssao -o " + path("x.exr"));
    EXPECT_EQ(ssao.status, 1);
    EXPECT_NE(ssao.err.find("--ao rt"), std::string::npos) << ssao.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
    EXPECT_FALSE(fs::exists(path("x_deep.exr")));
    EXPECT_TRUE(noTemporaries());
    // dhdr-aa takes the deep G-buffer's front samples for its edges (read strip by strip):
    // the edges of the --flat G-buffer, which holds each pixel's first surface.
    const Result aa = run("dhdr-aa " + path("dflat.exr") + " --gbuffer " + path("dg.exr") + " -o " +
                          path("daa.exr"));
    EXPECT_EQ(aa.status, 0) << aa.err;
    EXPECT_TRUE(allFinite(read("daa.exr")));
    ASSERT_EQ(
        run("dhdr-gbuffer " + kGlass + " --size 80x300 --flat -o " + path("dgflat.exr")).status, 0);
    ASSERT_EQ(run("dhdr-aa " + path("dflat.exr") + " --gbuffer " + path("dgflat.exr") + " -o " +
                  path("daa_flat.exr"))
                  .status,
              0);
    const ImageBuf fromDeep = read("daa.exr"), fromFlat = read("daa_flat.exr");
    EXPECT_EQ(OIIO::ImageBufAlgo::compare(fromDeep, fromFlat, 0.0f, 0.0f).nfail, 0u);
    EXPECT_GT(OIIO::ImageBufAlgo::compare(fromDeep, read("dflat.exr"), 1e-4f, 1e-4f).nfail, 0u);
}

// A light far too bright for half: the flat output clamps to 65504 with a warning, and the
// --deep-out file follows the same rule (it wrote +Inf samples before).
TEST_F(LightTools, DeepOutputHoldsNoInfinityWhereHalfOverflows) {
    ASSERT_EQ(run("dhdr-gbuffer " + kGlass + " --size 32x32 -o " + path("ig.exr")).status, 0);
    std::ofstream(path("blinding.json"))
        << R"({"lights": [{"type": "ambient", "name": "blinding", "intensity": 1e9}]})";
    const Result r = run("dhdr-light " + path("ig.exr") + " --lights " + path("blinding.json") +
                         " --deep-out " + path("ideep.exr") + " -o " + path("iflat.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("65504"), std::string::npos) << r.err;
    EXPECT_TRUE(allFinite(read("iflat.exr")));
    OIIO::ImageBuf deep(path("ideep.exr"));
    ASSERT_TRUE(deep.read(0, 0, true));
    const OIIO::DeepData& d = *deep.deepdata();
    int samples = 0, clamped = 0;
    for (int64_t p = 0; p < d.pixels(); ++p)
        for (int k = 0; k < d.samples(p); ++k)
            for (int c = 0; c < d.channels(); ++c) {
                const float v = d.deep_value(p, c, k);
                ASSERT_TRUE(std::isfinite(v))
                    << "pixel " << p << " sample " << k << " channel " << c;
                clamped += v == 65504.0f;
                samples += c == 0;
            }
    EXPECT_GT(samples, 32 * 32 / 2);
    EXPECT_GT(clamped, 0);
}

// dhdr-probes takes dhdr-light's --radiometric: the same lights bake to 1/683 the irradiance.
TEST_F(LightTools, ProbesTakeTheLightUnitsOfDhdrLight) {
    const std::string spheres = kTestdata + "/spheres.gltf";
    std::ofstream(path("point.json"))
        << R"({"lights": [{"type": "point", "position": [0.3, 2.0, 1.0], "intensity": 500}]})";
    const std::string bake = "dhdr-probes " + spheres + " --lights " + path("point.json") +
                             " --grid 2,2,2 --rays 64 --bounces 1 ";
    ASSERT_EQ(run(bake + "-o " + path("photometric.probes.exr")).status, 0);
    const Result r = run(bake + "--radiometric -o " + path("radiometric.probes.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf a = read("photometric.probes.exr"), b = read("radiometric.probes.exr");
    ASSERT_EQ(a.spec().image_pixels(), b.spec().image_pixels());
    int compared = 0;
    for (int y = 0; y < a.spec().height; ++y)
        for (int x = 0; x < a.spec().width; ++x)
            for (int c = 0; c < 3; ++c) {
                const float p = a.getchannel(x, y, 0, c), q = b.getchannel(x, y, 0, c);
                if (!(p > 1e-3f)) continue;
                EXPECT_NEAR(q * 683.0f / p, 1.0f, 3e-3f) << x << "," << y;
                ++compared;
            }
    EXPECT_GT(compared, 100);
}

// A probe file says which diffuse model its bake reflected with, and dhdr-light warns when it
// shades with another (the indirect light would not match the direct).
TEST_F(LightTools, ProbesRecordTheirDiffuseModel) {
    const std::string spheres = kTestdata + "/spheres.gltf";
    const std::string bake = "dhdr-probes " + spheres + " --grid 2,2,2 --rays 64 --bounces 1 ";
    ASSERT_EQ(run(bake + "--diffuse burley -o " + path("burley.probes.exr")).status, 0);
    ASSERT_EQ(run(bake + "-o " + path("lambert.probes.exr")).status, 0);
    EXPECT_EQ(read("burley.probes.exr").spec().get_string_attribute("dhdr:probeDiffuse"), "burley");
    EXPECT_EQ(read("lambert.probes.exr").spec().get_string_attribute("dhdr:probeDiffuse"),
              "lambert");
    const std::string light = "dhdr-light " + path("g.exr") + " --scene " + kCornell + " -o " +
                              path("d.exr") + " --probes ";
    Result r = run(light + path("burley.probes.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("burley.probes.exr: baked with --diffuse burley, shaded here with "
                         "lambert"),
              std::string::npos)
        << r.err;
    r = run(light + path("burley.probes.exr") + " --diffuse burley");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find("baked with"), std::string::npos) << r.err;
}

// The lights options come from one place: dhdr-light and dhdr-probes explain them in the same
// words and refuse the same values with the same message.
TEST_F(LightTools, ProbesAndLightShareTheirLightsOptions) {
    auto helpOf = [&](const std::string& tool, const std::string& option) {
        const Result r = run(tool + " --help");
        EXPECT_EQ(r.status, 0);
        const std::string text = r.out + r.err;
        const size_t at = text.find("\n  " + option);
        EXPECT_NE(at, std::string::npos) << tool << " " << option;
        // The option's line and its continuation lines, up to the next option.
        const size_t end = text.find("\n  -", at + 1);
        return text.substr(at, end - at);
    };
    for (const char* option : {"--lights", "--radiometric", "--emissive-lights", "--diffuse"}) {
        const std::string a = helpOf("dhdr-light", option), b = helpOf("dhdr-probes", option);
        EXPECT_FALSE(a.empty());
        EXPECT_EQ(a, b) << option;
    }
    const std::string scene = kTestdata + "/spheres.gltf";
    const Result light = run("dhdr-light " + path("none.exr") + " --scene " + scene +
                             " --emissive-lights maybe -o " + path("x.exr"));
    const Result probes =
        run("dhdr-probes " + scene + " --emissive-lights maybe -o " + path("x.probes.exr"));
    EXPECT_EQ(light.status, 2);
    EXPECT_EQ(probes.status, 2);
    EXPECT_NE(probes.err.find("--emissive-lights must be on or off"), std::string::npos)
        << probes.err;
    EXPECT_NE(light.err.find("--emissive-lights must be on or off"), std::string::npos)
        << light.err;
}

TEST_F(LightTools, ProbesAddIndirectLightAndTheirAOV) {
    // dhdr-probes bakes the Cornell box; dhdr-light --probes lights what faces away from every
    // light (the bounce off the walls), --aovs writes that light as indirect.R/G/B, and the
    // output is the same for any thread count.
    const Result bake =
        run("dhdr-probes " + kCornell + " --spacing 0.15 -o " + path("cb.probes.exr") + " -v");
    ASSERT_EQ(bake.status, 0) << bake.err;
    EXPECT_NE(bake.err.find("relocated"), std::string::npos) << bake.err;
    ASSERT_EQ(run("dhdr-light --gi direct " + path("g.exr") + " --scene " + kCornell +
                  " --type float -o " + path("nogi.exr"))
                  .status,
              0);
    const Result lit =
        run("dhdr-light " + path("g.exr") + " --scene " + kCornell + " --probes " +
            path("cb.probes.exr") + " --aovs --type float -o " + path("gi.exr") + " --threads 1");
    ASSERT_EQ(lit.status, 0) << lit.err;
    ASSERT_EQ(run("dhdr-light " + path("g.exr") + " --scene " + kCornell + " --probes " +
                  path("cb.probes.exr") + " --aovs --type float -o " + path("gi2.exr") +
                  " --threads 2")
                  .status,
              0);
    const ImageBuf gi = read("gi.exr"), nogi = read("nogi.exr");
    EXPECT_TRUE(samePixels(gi, read("gi2.exr")));
    const int ir = gi.spec().channelindex("indirect.R");
    ASSERT_GE(ir, 0);
    int brighter = 0, covered = 0;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x) {
            if (nogi.getchannel(x, y, 0, 3) <= 0.0f) continue;
            ++covered;
            float sum = 0.0f;
            for (int c = 0; c < 3; ++c) {
                const float indirect = gi.getchannel(x, y, 0, ir + c);
                EXPECT_GE(indirect, 0.0f);
                // The lit image is the unlit one plus the indirect light.
                EXPECT_NEAR(gi.getchannel(x, y, 0, c), nogi.getchannel(x, y, 0, c) + indirect,
                            1e-4f + 1e-4f * std::abs(nogi.getchannel(x, y, 0, c)));
                sum += indirect;
            }
            brighter += sum > 0.0f;
        }
    EXPECT_GT(brighter, covered * 9 / 10);
    // A file that is not a probe volume is an error naming it.
    const Result bad = run("dhdr-light " + path("g.exr") + " --scene " + kCornell + " --probes " +
                           path("g.exr") + " -o " + path("x.exr"));
    EXPECT_EQ(bad.status, 1);
    EXPECT_NE(bad.err.find("not a probe volume"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
    const Result usage = run("dhdr-probes " + kCornell + " --grid 0,2,2 -o " + path("x.exr"));
    EXPECT_EQ(usage.status, 2);
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

namespace {

// dhdr's own G-buffer rewritten as Blender writes its passes: ViewLayer.* names, a Z-up world,
// depth 1e10 on the background, alpha 1 everywhere, no camera matrices; the base colour,
// roughness and metallic as the AOVs a user adds (or the albedo as DiffCol without them).
void writeBlenderPasses(const ImageBuf& g, const std::string& out, bool aovs) {
    std::vector<BlenderChannel> extra = {
        {"ViewLayer.Combined.R", "", 0.1f}, {"ViewLayer.Combined.G", "", 0.1f},
        {"ViewLayer.Combined.B", "", 0.1f}, {"ViewLayer.Combined.A", "", 1.0f},
        {"ViewLayer.Emit.R", "emission.R"}, {"ViewLayer.Emit.G", "emission.G"},
        {"ViewLayer.Emit.B", "emission.B"}};
    if (aovs)
        extra.insert(extra.end(), {{"ViewLayer.BaseColor.R", "albedo.R"},
                                   {"ViewLayer.BaseColor.G", "albedo.G"},
                                   {"ViewLayer.BaseColor.B", "albedo.B"},
                                   {"ViewLayer.Roughness.X", "roughness"},
                                   {"ViewLayer.Metallic.X", "metallic"}});
    else
        extra.insert(extra.end(), {{"ViewLayer.DiffCol.R", "albedo.R"},
                                   {"ViewLayer.DiffCol.G", "albedo.G"},
                                   {"ViewLayer.DiffCol.B", "albedo.B"}});
    dhdr::test::writeBlenderPasses(g, out, extra);
}

} // namespace

TEST_F(LightTools, BlenderPassesRelightAsDhdrsOwnGBuffer) {
    ImageBuf g = read("g.exr");
    writeBlenderPasses(g, path("blender.exr"), true);
    writeBlenderPasses(g, path("blender_noaov.exr"), false);
    std::ofstream(path("point.lights.json"))
        << R"({"lights": [{"type": "point", "position": [0.3, 0.4, 0.25], "intensity": 0.3}]})";
    const std::string lights = " --lights " + path("point.lights.json") + " --type float";
    ASSERT_EQ(run("dhdr-light " + path("g.exr") + lights + " -o " + path("own.exr")).status, 0);
    const Result r =
        run("dhdr-light " + path("blender.exr") + lights + " --channels blender --camera-from " +
            kCornell + " -o " + path("relit.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf own = read("own.exr"), relit = read("relit.exr");
    const auto cmp = OIIO::ImageBufAlgo::compare(own, relit, 1e-4f, 1e-4f);
    EXPECT_EQ(cmp.nfail, 0u) << "max error " << cmp.maxerror << " at " << cmp.maxx << ","
                             << cmp.maxy;
    // --radiometric: Blender's watts → candela conversion undone, 1/683 of the light.
    ASSERT_EQ(run("dhdr-light " + path("blender.exr") + lights +
                  " --channels blender --camera-from " + kCornell + " --radiometric -o " +
                  path("radiometric.exr"))
                  .status,
              0);
    const ImageBuf rad = read("radiometric.exr");
    for (int y = 0; y < 96; y += 5)
        for (int x = 0; x < 96; x += 5)
            EXPECT_NEAR(rad.getchannel(x, y, 0, 0), relit.getchannel(x, y, 0, 0) / 683.0f,
                        1e-6f + 1e-4f * relit.getchannel(x, y, 0, 0) / 683.0f);
    // Without the AOVs: DiffCol as the albedo, with warnings that say what stands in.
    const Result fallback =
        run("dhdr-light " + path("blender_noaov.exr") + lights +
            " --channels blender --camera-from " + kCornell + " -o " + path("fallback.exr"));
    EXPECT_EQ(fallback.status, 0) << fallback.err;
    EXPECT_NE(fallback.err.find("DiffCol"), std::string::npos) << fallback.err;
    EXPECT_NE(fallback.err.find("Roughness"), std::string::npos) << fallback.err;
    // Without a camera: an error that says how to give one.
    const Result noCamera = run("dhdr-light " + path("blender.exr") + lights +
                                " --channels blender -o " + path("x.exr"));
    EXPECT_EQ(noCamera.status, 1);
    EXPECT_NE(noCamera.err.find("--camera-from"), std::string::npos) << noCamera.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
    // A map whose normal, not marked required, names channels the passes lack: the error
    // names the map and the channel, since lighting needs a normal whatever the map says.
    std::ofstream(path("nonormal.json"))
        << R"({"depth": {"channels": ["ViewLayer.Depth.Z"]}, "position": {"channels": [)"
           R"("ViewLayer.Position.X", "ViewLayer.Position.Y", "ViewLayer.Position.Z"]},)"
           R"( "normal": {"channels": ["N.x", "N.y", "N.z"]}})";
    const Result noNormal =
        run("dhdr-light " + path("blender.exr") + lights + " --channels " + path("nonormal.json") +
            " --camera-from " + kCornell + " -o " + path("x.exr"));
    EXPECT_EQ(noNormal.status, 1);
    EXPECT_NE(noNormal.err.find("nonormal.json"), std::string::npos) << noNormal.err;
    EXPECT_NE(noNormal.err.find("'N.x'"), std::string::npos) << noNormal.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

// --gi auto (the default) with the scene and no --probes: the probes dhdr-probes bakes at its
// defaults, baked in the run, lighting the frame to the bit as the file does; none under an
// environment light; --gi direct is the frame without them.
TEST_F(LightTools, GiAutoBakesWhatDhdrProbesBakes) {
    const Result auto_ = run("dhdr-light " + path("g.exr") + " --scene " + kCornell +
                             " --type float -v -o " + path("gi_auto.exr"));
    ASSERT_EQ(auto_.status, 0) << auto_.err;
    EXPECT_NE(auto_.err.find("--gi auto: indirect light from probes baked"), std::string::npos)
        << auto_.err;
    EXPECT_NE(auto_.err.find("512 probes baked"), std::string::npos) << auto_.err;
    ASSERT_EQ(run("dhdr-probes " + kCornell + " -q -o " + path("gi_auto.probes.exr")).status, 0);
    ASSERT_EQ(run("dhdr-light " + path("g.exr") + " --scene " + kCornell + " --probes " +
                  path("gi_auto.probes.exr") + " --type float -o " + path("gi_file.exr"))
                  .status,
              0);
    const ImageBuf baked = read("gi_auto.exr");
    EXPECT_TRUE(samePixels(baked, read("gi_file.exr")));

    // The probes only add light: every covered pixel at least the direct frame's, and the
    // surfaces no light reaches directly (the blocks' fronts) lit.
    ASSERT_EQ(run("dhdr-light " + path("g.exr") + " --scene " + kCornell +
                  " --gi direct --type float -o " + path("gi_direct.exr"))
                  .status,
              0);
    const ImageBuf direct = read("gi_direct.exr");
    double added = 0.0, total = 0.0;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x)
            for (int c = 0; c < 3; ++c) {
                const float a = baked.getchannel(x, y, 0, c), d = direct.getchannel(x, y, 0, c);
                EXPECT_GE(a, d * (1.0f - 1e-5f)) << x << "," << y;
                added += a - d;
                total += d;
            }
    EXPECT_GT(added, 0.1 * total);

    // Under an environment light no probes are baked, and -v says why.
    writeSky(path("gi_sky.exr"), 64);
    std::ofstream(path("gi_sky.json"))
        << R"({"lights": [{"type": "environment", "image": "gi_sky.exr"}]})";
    const Result open = run("dhdr-light " + path("g.exr") + " --scene " + kCornell + " --lights " +
                            path("gi_sky.json") + " --type float -v -o " + path("gi_open.exr"));
    ASSERT_EQ(open.status, 0) << open.err;
    EXPECT_NE(open.err.find("no probes baked under an environment light"), std::string::npos)
        << open.err;
    EXPECT_EQ(open.err.find("probes baked in"), std::string::npos) << open.err;
    ASSERT_EQ(run("dhdr-light " + path("g.exr") + " --scene " + kCornell + " --lights " +
                  path("gi_sky.json") + " --gi direct --type float -o " + path("gi_open_d.exr"))
                  .status,
              0);
    EXPECT_TRUE(samePixels(read("gi_open.exr"), read("gi_open_d.exr")));

    // Probes that cannot be baked (their light past float's range) leave the frame its direct
    // light, with a warning, as --gi direct makes it.
    std::ofstream(path("gi_huge.json"))
        << R"({"lights": [{"type": "point", "position": [0.28, 0.5, 0.28], "intensity": 3e38}]})";
    const std::string huge = "dhdr-light " + path("g.exr") + " --scene " + kCornell + " --lights " +
                             path("gi_huge.json") + " --type float -o ";
    const Result h = run(huge + path("gi_huge.exr"));
    ASSERT_EQ(h.status, 0) << h.err;
    EXPECT_NE(h.err.find("the probes cannot be baked"), std::string::npos) << h.err;
    ASSERT_EQ(run(huge + path("gi_huge_d.exr") + " --gi direct").status, 0);
    EXPECT_TRUE(samePixels(read("gi_huge.exr"), read("gi_huge_d.exr")));
}
