// dhdr-light over an animated shot (issue 24), as a user runs it: --scene posed at the moment
// each G-buffer records, so that a moving object's shadow and the scene's own lights move with
// it; G-buffers that record no moment lit as before; motion vectors passed through, Blender's
// Vector pass included.
#include "animation_writer.h"
#include "blender_passes.h"
#include "tool_test.h"

#include <OpenImageIO/imagebufalgo.h>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>

using namespace dhdr::test;

namespace {

class PosedLighting : public ToolTest {
protected:
    static void SetUpTestSuite() {
        makeScratch();
        // A floor (z = 0, 6 × 6 units, wider than the 4 × 4 view) and a block (a 0.5 × 0.5
        // square at z = 0.75) above it that slides +x 0.25 units a frame at 24 fps, from
        // x = −1 at t = 0. At frame 6 (t = 0.25 s) it is at x = 0.5: the numbers are all
        // exact in binary, so the animated and the baked file give the same vertices.
        nlohmann::json doc = squareAndCamera();
        doc["nodes"][0]["name"] = "floor";
        doc["nodes"][0]["scale"] = {6.0, 6.0, 1.0};
        doc["nodes"].push_back({{"name", "block"},
                                {"mesh", 0},
                                {"translation", {-1.0, 0.0, 0.75}},
                                {"scale", {0.5, 0.5, 1.0}}});
        doc["scenes"][0]["nodes"] = {0, 1, 2};
        writeJson(path("rest.gltf"), doc);
        nlohmann::json baked = doc;
        baked["nodes"][2]["translation"] = {0.5, 0.0, 0.75};
        writeJson(path("baked.gltf"), baked);
        addChannel(doc, 0, 2, "translation", {0.0f, 2.0f}, {-1, 0, 0.75f, 11, 0, 0.75f});
        writeJson(path("anim.gltf"), doc);
        // Light travelling +x and down at 45°: the block's shadow falls 0.75 units to its right
        // (x0 + 0.5 … x0 + 1), with edges on pixel boundaries, half a pixel from any ray.
        std::ofstream(path("sun.lights.json"))
            << R"({"lights": [{"type": "directional", "direction": [1, 0, -1], "intensity": 3}]})";
        ASSERT_EQ(run("dhdr-gbuffer " + path("anim.gltf") + " --size 64x64 --frame 6 -o " +
                      path("anim6.gbuf.exr"))
                      .status,
                  0);
    }

    // Lights `gbuffer` with `scene` and `extra` options into `out` (float); the result.
    static Result light(const std::string& gbuffer, const std::string& scene,
                        const std::string& out, const std::string& extra = "") {
        // Direct light: the probes --gi auto would bake over the posed scene (its block an
        // instance) and over the static file differ in their last bits.
        return run("dhdr-light " + path(gbuffer) + " --scene " + path(scene) +
                   " --gi direct --type float -o " + path(out) + " " + extra);
    }

    static bool sameBits(const ImageBuf& a, const ImageBuf& b) {
        const size_t n = a.spec().image_pixels() * size_t(a.nchannels());
        return a.nchannels() == b.nchannels() &&
               a.spec().image_pixels() == b.spec().image_pixels() &&
               std::memcmp(a.localpixels(), b.localpixels(), n * sizeof(float)) == 0;
    }

    // Whether the floor's pixels in columns [x0, x1), rows 28–35 (the block's y) are all dark.
    static bool shadowed(const ImageBuf& lit, int x0, int x1) {
        for (int y = 28; y < 36; ++y)
            for (int x = x0; x < x1; ++x)
                if (lit.getchannel(x, y, 0, 0) != 0.0f) return false;
        return true;
    }
    static bool lit(const ImageBuf& img, int x0, int x1) {
        for (int y = 28; y < 36; ++y)
            for (int x = x0; x < x1; ++x)
                if (!(img.getchannel(x, y, 0, 0) > 0.0f)) return false;
        return true;
    }

    // A copy of the EXR `from` with its header changed by `edit`, every channel in its own
    // type (ids stay uint).
    static void rewriteHeader(const std::string& from, const std::string& to,
                              const std::function<void(OIIO::ImageSpec&)>& edit) {
        auto in = OIIO::ImageInput::open(path(from));
        ASSERT_TRUE(in);
        OIIO::ImageSpec spec = in->spec();
        std::vector<unsigned char> pixels(spec.image_bytes(true));
        ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeUnknown, pixels.data()));
        edit(spec);
        auto out = OIIO::ImageOutput::create(path(to));
        ASSERT_TRUE(out && out->open(path(to), spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeUnknown, pixels.data()));
        out->close();
    }
};

} // namespace

// The G-buffer says which moment and which animations: the time and frame rate as doubles
// (the numbers the scene was posed with), the animations as indices.
TEST_F(PosedLighting, AnAnimatedGBufferRecordsItsMoment) {
    const ImageBuf g = read("anim6.gbuf.exr");
    const OIIO::ParamValue* t = g.spec().find_attribute("dhdr:animationTime");
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(t->type(), OIIO::TypeDesc::DOUBLE);
    EXPECT_EQ(*static_cast<const double*>(t->data()), 0.25);
    EXPECT_EQ(g.spec().find_attribute("dhdr:fps")->type(), OIIO::TypeDesc::DOUBLE);
    EXPECT_EQ(g.spec().get_string_attribute("dhdr:animation"), "0");
    // A deep one too (its header goes through OpenEXR itself).
    ASSERT_EQ(run("dhdr-gbuffer " + path("anim.gltf") + " --size 16x16 --frame 5 --deep -o " +
                  path("deep5.gbuf.exr"))
                  .status,
              0);
    auto in = OIIO::ImageInput::open(path("deep5.gbuf.exr"));
    ASSERT_TRUE(in);
    const OIIO::ParamValue* d = in->spec().find_attribute("dhdr:animationTime");
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(d->type(), OIIO::TypeDesc::DOUBLE);
    EXPECT_EQ(*static_cast<const double*>(d->data()), 5.0 / 24.0);
}

// Frame 6: the block's shadow under dhdr-light --scene anim.gltf is, bit for bit, the shadow
// of the static file with frame 6's translation baked in, lighting the same G-buffer: columns
// 48–55 dark. It is not where the rest pose would cast it (columns 24–31).
TEST_F(PosedLighting, AMovingBlocksShadowIsTheStaticFilesAtItsFrame) {
    const std::string sun = "--lights " + path("sun.lights.json");
    const Result posed = light("anim6.gbuf.exr", "anim.gltf", "posed.exr", sun + " -v");
    ASSERT_EQ(posed.status, 0) << posed.err;
    EXPECT_NE(posed.err.find("posed at 0.25"), std::string::npos) << posed.err;
    ASSERT_EQ(light("anim6.gbuf.exr", "baked.gltf", "baked.exr", sun).status, 0);
    const ImageBuf a = read("posed.exr"), b = read("baked.exr");
    EXPECT_TRUE(sameBits(a, b));
    EXPECT_TRUE(shadowed(a, 48, 56));
    EXPECT_TRUE(lit(a, 24, 32));
    EXPECT_TRUE(lit(a, 56, 64)); // right of the shadow
    // The rest pose's shadow, for contrast: what dhdr-light drew before it posed the scene.
    ASSERT_EQ(light("anim6.gbuf.exr", "rest.gltf", "rest.exr", sun).status, 0);
    const ImageBuf r = read("rest.exr");
    EXPECT_TRUE(shadowed(r, 24, 32));
    EXPECT_FALSE(sameBits(a, r));
    // One process over a sequence: each frame posed at its own time (frame 2: x0 = −0.5, the
    // shadow at x 0 … 0.5, columns 32–39).
    ASSERT_EQ(run("dhdr-gbuffer " + path("anim.gltf") + " --size 64x64 --frames 1-2 -o " +
                  path("seq.#.gbuf.exr"))
                  .status,
              0);
    const Result seq =
        run("dhdr-light " + path("seq.#.gbuf.exr") + " --frames 1-2 --scene " + path("anim.gltf") +
            " " + sun + " --gi direct --type float -o " + path("seq.#.hdr.exr"));
    ASSERT_EQ(seq.status, 0) << seq.err;
    EXPECT_TRUE(shadowed(read("seq.2.hdr.exr"), 32, 40));
    EXPECT_TRUE(shadowed(read("seq.1.hdr.exr"), 28, 36));
}

// A G-buffer that records no moment (one rendered before G-buffers recorded it, or another
// renderer's) is lit against the file's rest pose, as before: the same bits as with a copy of
// the file without its animation, and a warning that says so.
TEST_F(PosedLighting, AGBufferWithoutATimeIsLitAsBefore) {
    rewriteHeader("anim6.gbuf.exr", "notime.gbuf.exr", [](OIIO::ImageSpec& s) {
        for (const char* a : {"dhdr:animationTime", "dhdr:fps", "dhdr:animation"})
            s.erase_attribute(a);
    });
    const std::string sun = "--lights " + path("sun.lights.json");
    const Result r = light("notime.gbuf.exr", "anim.gltf", "notime_anim.exr", sun);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("records no animation time"), std::string::npos) << r.err;
    ASSERT_EQ(light("notime.gbuf.exr", "rest.gltf", "notime_rest.exr", sun).status, 0);
    const ImageBuf a = read("notime_anim.exr"), b = read("notime_rest.exr");
    EXPECT_TRUE(sameBits(a, b));
    EXPECT_TRUE(shadowed(a, 24, 32));
    // A G-buffer from before the animations were recorded: the first animation plays.
    rewriteHeader("anim6.gbuf.exr", "noanim.gbuf.exr",
                  [](OIIO::ImageSpec& s) { s.erase_attribute("dhdr:animation"); });
    ASSERT_EQ(light("noanim.gbuf.exr", "anim.gltf", "noanim.exr", sun).status, 0);
    ASSERT_EQ(light("anim6.gbuf.exr", "anim.gltf", "posed.exr", sun).status, 0);
    EXPECT_TRUE(sameBits(read("noanim.exr"), read("posed.exr")));
}

// Which animations play is what the G-buffer was rendered with: --animation 1 is recorded and
// posed; one the scene does not have, or a record that is not indices, is an error naming the
// G-buffer, with no output.
TEST_F(PosedLighting, TheRecordedAnimationsPlay) {
    nlohmann::json doc = nlohmann::json::parse(slurp(path("anim.gltf")));
    // Animation 1 moves the block the other way: x = −1 − 6t, at frame 6 x = −2.5.
    addChannel(doc, 1, 2, "translation", {0.0f, 2.0f}, {-1, 0, 0.75f, -13, 0, 0.75f});
    writeJson(path("two.gltf"), doc);
    ASSERT_EQ(run("dhdr-gbuffer " + path("two.gltf") + " --size 64x64 --frame 6 --animation 1 -o " +
                  path("two6.gbuf.exr"))
                  .status,
              0);
    EXPECT_EQ(read("two6.gbuf.exr").spec().get_string_attribute("dhdr:animation"), "1");
    nlohmann::json baked = nlohmann::json::parse(slurp(path("baked.gltf")));
    baked["nodes"][2]["translation"] = {-2.5, 0.0, 0.75};
    writeJson(path("baked1.gltf"), baked);
    const std::string sun = "--lights " + path("sun.lights.json");
    ASSERT_EQ(light("two6.gbuf.exr", "two.gltf", "two6.exr", sun).status, 0);
    ASSERT_EQ(light("two6.gbuf.exr", "baked1.gltf", "baked1.exr", sun).status, 0);
    EXPECT_TRUE(sameBits(read("two6.exr"), read("baked1.exr")));
    // The one-animation file has no animation 1.
    const Result missing = light("two6.gbuf.exr", "anim.gltf", "missing.exr", sun);
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.err.find("two6.gbuf.exr: rendered with animation 1"), std::string::npos)
        << missing.err;
    EXPECT_FALSE(fs::exists(path("missing.exr")));
    rewriteHeader("anim6.gbuf.exr", "bad.gbuf.exr",
                  [](OIIO::ImageSpec& s) { s.attribute("dhdr:animation", "walk"); });
    const Result bad = light("bad.gbuf.exr", "anim.gltf", "bad.exr", sun);
    EXPECT_EQ(bad.status, 1);
    EXPECT_NE(bad.err.find("bad.gbuf.exr: dhdr:animation 'walk'"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(path("bad.exr")));
    EXPECT_TRUE(noTemporaries());
}

// Without --lights the scene lights itself: its punctual lights and its glowing meshes are where
// the animation puts them at the G-buffer's time, as in the file with the frame baked in.
TEST_F(PosedLighting, TheScenesOwnLightsMoveWithIt) {
    // The block glows, and a lamp rides 1 unit above it.
    auto withLights = [](nlohmann::json doc) { return withGlowAndLamp(std::move(doc), 1.0f); };
    writeJson(path("lamps.gltf"), withLights(nlohmann::json::parse(slurp(path("anim.gltf")))));
    writeJson(path("lamps_baked.gltf"),
              withLights(nlohmann::json::parse(slurp(path("baked.gltf")))));
    writeJson(path("lamps_rest.gltf"), withLights(nlohmann::json::parse(slurp(path("rest.gltf")))));
    const std::string opts = "--shadow-samples 4";
    ASSERT_EQ(light("anim6.gbuf.exr", "lamps.gltf", "lamps.exr", opts).status, 0);
    ASSERT_EQ(light("anim6.gbuf.exr", "lamps_baked.gltf", "lamps_baked.exr", opts).status, 0);
    ASSERT_EQ(light("anim6.gbuf.exr", "lamps_rest.gltf", "lamps_rest.exr", opts).status, 0);
    const ImageBuf a = read("lamps.exr");
    EXPECT_TRUE(sameBits(a, read("lamps_baked.exr")));
    EXPECT_FALSE(sameBits(a, read("lamps_rest.exr")));
}

// --aovs passes the G-buffer's motion layer through, dhdr's own and Blender's Vector pass read
// through --channels blender alike, so that dhdr-motionblur needs no --gbuffer: the same bits
// as with it.
TEST_F(PosedLighting, MotionPassesThroughDhdrLightWithAovs) {
    const ImageBuf g = read("anim6.gbuf.exr");
    // The frame as Blender writes its passes, with its Vector pass.
    writeBlenderPasses(g, path("blender6.exr"),
                       {{"ViewLayer.Vector.X", "motion.X"},
                        {"ViewLayer.Vector.Y", "motion.Y"},
                        {"ViewLayer.Vector.Z", "motion.Z"},
                        {"ViewLayer.Vector.W", "motion.W"}});
    auto at = [&](int x, int y, const char* name) {
        return g.getchannel(x, y, 0, g.spec().channelindex(name));
    };
    // A lamp near the block, so that its top is brighter than the floor: edges to blur.
    std::ofstream(path("lamp.lights.json"))
        << R"({"lights": [{"type": "point", "position": [0.5, 0, 1.5], "intensity": 3}]})";
    const std::string sun = " --lights " + path("lamp.lights.json") + " --type float";
    const Result r =
        run("dhdr-light " + path("blender6.exr") + sun + " --channels blender --camera-from " +
            path("anim.gltf") + " --aovs -o " + path("bl.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    ASSERT_EQ(
        run("dhdr-light " + path("anim6.gbuf.exr") + sun + " --aovs -o " + path("own.exr")).status,
        0);
    const ImageBuf bl = read("bl.exr"), own = read("own.exr");
    const char* motion[4] = {"motion.X", "motion.Y", "motion.Z", "motion.W"};
    for (const ImageBuf* out : {&bl, &own}) {
        const int m = out->spec().channelindex("motion.X");
        ASSERT_GE(m, 0);
        int moving = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x)
                for (int c = 0; c < 4; ++c) {
                    const float want = at(x, y, motion[c]);
                    ASSERT_EQ(out->getchannel(x, y, 0, m + c), want) << x << "," << y;
                    moving += want != 0.0f;
                }
        EXPECT_GT(moving, 60); // the block's pixels, X and Z
    }
    // dhdr-motionblur on the lit frame alone equals it with the G-buffer given.
    for (const char* file : {"bl.exr", "own.exr"}) {
        ASSERT_EQ(
            run(std::string("dhdr-motionblur ") + path(file) + " -o " + path("mb_self.exr")).status,
            0)
            << file;
        ASSERT_EQ(run(std::string("dhdr-motionblur ") + path(file) + " --gbuffer " +
                      path("anim6.gbuf.exr") + " -o " + path("mb_g.exr"))
                      .status,
                  0);
        const ImageBuf self = read("mb_self.exr"), given = read("mb_g.exr");
        EXPECT_TRUE(sameBits(self, given)) << file;
        EXPECT_FALSE(sameBits(self, read(file))) << file; // it did blur
    }
    // A channel map names the vectors itself; scale −1 turns their sign around. Three names
    // for them is an error naming the map.
    const std::string axes =
        R"("depth": {"channels": ["ViewLayer.Depth.Z"]},)"
        R"( "position": {"channels": ["ViewLayer.Position.X",)"
        R"( "ViewLayer.Position.Y", "ViewLayer.Position.Z"], "axes": "z-up"},)"
        R"( "normal": {"channels": ["ViewLayer.Normal.X", "ViewLayer.Normal.Y",)"
        R"( "ViewLayer.Normal.Z"], "axes": "z-up"},)";
    std::ofstream(path("vectors.map.json"))
        << "{" << axes
        << R"( "motion": {"channels": ["ViewLayer.Vector.X", "ViewLayer.Vector.Y",)"
           R"( "ViewLayer.Vector.Z", "ViewLayer.Vector.W"], "scale": -1}})";
    const Result mapped =
        run("dhdr-light " + path("blender6.exr") + sun + " --channels " + path("vectors.map.json") +
            " --camera-from " + path("anim.gltf") + " --aovs -o " + path("mapped.exr"));
    ASSERT_EQ(mapped.status, 0) << mapped.err;
    const ImageBuf m = read("mapped.exr");
    const int mx = m.spec().channelindex("motion.X");
    ASSERT_GE(mx, 0);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            ASSERT_EQ(m.getchannel(x, y, 0, mx + 2), -at(x, y, "motion.Z")) << x << "," << y;
    std::ofstream(path("three.map.json"))
        << "{" << axes << R"( "motion": {"channels": ["A", "B", "C"]}})";
    const Result three =
        run("dhdr-light " + path("blender6.exr") + sun + " --channels " + path("three.map.json") +
            " --camera-from " + path("anim.gltf") + " -o " + path("three.exr"));
    EXPECT_EQ(three.status, 1);
    EXPECT_NE(three.err.find("three.map.json: motion: needs 4 channel names"), std::string::npos)
        << three.err;
    EXPECT_FALSE(fs::exists(path("three.exr")));
    // Without --aovs the output is R, G, B, A as before.
    ASSERT_EQ(run("dhdr-light " + path("blender6.exr") + sun +
                  " --channels blender --camera-from " + path("anim.gltf") + " -o " +
                  path("bl_plain.exr"))
                  .status,
              0);
    EXPECT_EQ(read("bl_plain.exr").nchannels(), 4);
}
