// Light probes over an animated shot (issue 24), as a user runs the tools: dhdr-probes --frames
// bakes each frame with the scene posed at its time, as --frame N and as the static file with
// frame N's transforms baked in; dhdr-light --probes with a frame pattern lights each G-buffer
// with its own frame's probes; missing or mismatched files are clear.
#include "animation_writer.h"
#include "tool_test.h"

#include <OpenImageIO/imageio.h>
#include <cstring>
#include <fstream>

using namespace dhdr::test;

namespace {

class ProbeFrames : public ToolTest {
protected:
    static void SetUpTestSuite() {
        makeScratch();
        // A white floor (z = 0, 6 × 6 units, wider than the 4 × 4 view) and a white panel
        // standing on it (y from −1 to 1, z from 0 to 1) facing −X, towards a sun that
        // travels +x and down: the panel's lit face bounces light onto the floor in front of
        // it. The panel slides +x 2.5 units a second from x = −2.5 (t = 0) to 2.5 (t = 2);
        // its rest pose is x = 0.5, neither end. The rotation (±0.5 quaternion: a matrix of 0
        // and ±1) and every position are exact in binary, so that the posed scene and the
        // file with the pose baked in have the same vertices, in float or double.
        nlohmann::json doc = squareAndCamera();
        doc["nodes"][0]["name"] = "floor";
        doc["nodes"][0]["scale"] = {6.0, 6.0, 1.0};
        doc["nodes"].push_back({{"name", "panel"},
                                {"mesh", 0},
                                {"translation", {0.5, 0.0, 0.5}},
                                {"rotation", {0.5, -0.5, -0.5, 0.5}},
                                {"scale", {2.0, 1.0, 1.0}}});
        doc["scenes"][0]["nodes"] = {0, 1, 2};
        auto baked = [&](const char* name, double x) {
            nlohmann::json d = doc;
            d["nodes"][2]["translation"] = {x, 0.0, 0.5};
            writeJson(path(name), d);
        };
        // At 2 frames a second, frame 1 (0.5 s) has the panel at x = −1.25 and frame 2 (1 s)
        // at x = 0; frame 10 (5 s) holds the last key, x = 2.5, and frame −1 the first.
        baked("baked1.gltf", -1.25);
        baked("baked2.gltf", 0.0);
        baked("baked_end.gltf", 2.5);
        baked("baked_start.gltf", -2.5);
        addChannel(doc, 0, 2, "translation", {0.0f, 2.0f}, {-2.5f, 0, 0.5f, 2.5f, 0, 0.5f});
        writeJson(path("anim.gltf"), doc);
        std::ofstream(path("sun.lights.json"))
            << R"({"lights": [{"type": "directional", "direction": [1, 0, -1], "intensity": 3}]})";
    }

    // dhdr-probes on `scene` with the suite's bake (small: 0.1-0.3 s) and `extra` options.
    static Result bake(const std::string& scene, const std::string& out,
                       const std::string& extra = "") {
        return run("dhdr-probes " + path(scene) + " --lights " + path("sun.lights.json") +
                   " --max-probes 200 --rays 64 -o " + path(out) + " " + extra);
    }

    // Both parts' pixels and the grid's attributes of two probe files, bit for bit (their
    // recorded moments aside: a static file records none), or with `relative` > 0 each value
    // within that share of the larger.
    static void expectSameProbes(const std::string& a, const std::string& b,
                                 double relative = 0.0) {
        auto in = OIIO::ImageInput::open(path(a)), other = OIIO::ImageInput::open(path(b));
        ASSERT_TRUE(in && other) << a << " " << b;
        for (int part = 0; part < 2; ++part) {
            ASSERT_TRUE(in->seek_subimage(part, 0) && other->seek_subimage(part, 0));
            const OIIO::ImageSpec &s = in->spec(), &t = other->spec();
            ASSERT_EQ(s.width, t.width);
            ASSERT_EQ(s.height, t.height);
            ASSERT_EQ(s.nchannels, t.nchannels);
            for (const char* name : {"dhdr:probeOrigin", "dhdr:probeSpacing", "dhdr:probeCounts",
                                     "dhdr:probePositions", "dhdr:probeStates"}) {
                const OIIO::ParamValue *p = s.find_attribute(name), *q = t.find_attribute(name);
                ASSERT_TRUE(p && q) << name;
                ASSERT_EQ(p->type(), q->type()) << name;
                EXPECT_EQ(std::memcmp(p->data(), q->data(), p->type().size()), 0)
                    << a << " " << b << ": " << name;
            }
            std::vector<float> x(s.image_pixels() * size_t(s.nchannels)), y(x.size());
            ASSERT_TRUE(in->read_image(part, 0, 0, s.nchannels, OIIO::TypeDesc::FLOAT, x.data()));
            ASSERT_TRUE(
                other->read_image(part, 0, 0, t.nchannels, OIIO::TypeDesc::FLOAT, y.data()));
            if (relative == 0.0) {
                EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(float)), 0)
                    << a << " " << b << ": part " << part << " differs";
                continue;
            }
            // A probe ray grazing the panel's edge may go the other way (the last bits decide):
            // a few values of one probe may then differ by that ray's share, never more.
            size_t beyond = 0, worst = 0;
            double excess = 0.0;
            for (size_t i = 0; i < x.size(); ++i) {
                const double larger = std::max(std::abs(double(x[i])), std::abs(double(y[i])));
                const double d = std::abs(double(x[i]) - double(y[i]));
                if (d > relative * larger) ++beyond;
                if (d - 0.05 * larger > excess) {
                    excess = d - 0.05 * larger;
                    worst = i;
                }
            }
            EXPECT_LE(beyond, x.size() / 100) << a << " " << b << ": part " << part;
            EXPECT_EQ(excess, 0.0) << a << " " << b << ": part " << part << " value " << worst
                                   << ": " << x[worst] << " against " << y[worst];
        }
    }

    // How far a posed frame's probes may lie from the static file's with the pose baked in.
    // The moving panel is traced as an instance (docs/animation.md): a probe ray's hit on it
    // is found in the panel's own space, so its barycentrics, and with them the hit's point
    // and the shading there, may differ in their last bits; its error bound is larger, so the
    // rays leaving it start a few ulps further off. 2⁻¹⁶ is 256 float ulps of each value
    // (measured: 1 ulp); 1 % of the values may exceed it by up to 5 % (expectSameProbes).
    static constexpr double kInstanced = 0x1p-16;

    static bool sameBits(const ImageBuf& a, const ImageBuf& b) {
        const size_t n = a.spec().image_pixels() * size_t(a.nchannels());
        return a.nchannels() == b.nchannels() &&
               a.spec().image_pixels() == b.spec().image_pixels() &&
               std::memcmp(a.localpixels(), b.localpixels(), n * sizeof(float)) == 0;
    }

    // The mean of `img`'s indirect.R over floor columns [x0, x1), rows 24–39 (y from −0.5 to
    // 0.5, the panel's middle).
    static double indirect(const ImageBuf& img, int x0, int x1) {
        const int c = img.spec().channelindex("indirect.R");
        EXPECT_GE(c, 0);
        double sum = 0.0;
        for (int y = 24; y < 40; ++y)
            for (int x = x0; x < x1; ++x)
                sum += img.getchannel(x, y, 0, c);
        return sum / double(16 * (x1 - x0));
    }
};

} // namespace

// Frame 2 of one --frames run is, bit for bit, the probes of --frame 2 alone, and those of the
// static file with frame 2's translation baked in within kInstanced (whatever the thread
// count); the file
// records the moment as a G-buffer does (time and frame rate as doubles, the animations).
TEST_F(ProbeFrames, FrameNOfASequenceIsItsOwnBakeAndTheBakedStaticFiles) {
    const Result seq = bake("anim.gltf", "seq.#.probes.exr", "--fps 2 --frames 1-2 --threads 2 -v");
    ASSERT_EQ(seq.status, 0) << seq.err;
    EXPECT_NE(seq.err.find("time 1.000000 s"), std::string::npos) << seq.err;
    ASSERT_EQ(bake("anim.gltf", "one2.probes.exr", "--fps 2 --frame 2 --threads 1").status, 0);
    ASSERT_EQ(bake("baked2.gltf", "baked2.probes.exr").status, 0);
    expectSameProbes("seq.2.probes.exr", "one2.probes.exr");
    expectSameProbes("seq.2.probes.exr", "baked2.probes.exr", kInstanced);
    ASSERT_EQ(bake("baked1.gltf", "baked1.probes.exr").status, 0);
    expectSameProbes("seq.1.probes.exr", "baked1.probes.exr", kInstanced);
    // --time 1 is frame 2 at 2 frames a second.
    ASSERT_EQ(bake("anim.gltf", "t1.probes.exr", "--time 1 --fps 2").status, 0);
    expectSameProbes("t1.probes.exr", "one2.probes.exr");
    auto in = OIIO::ImageInput::open(path("seq.2.probes.exr"));
    ASSERT_TRUE(in);
    const OIIO::ParamValue* t = in->spec().find_attribute("dhdr:animationTime");
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(t->type(), OIIO::TypeDesc::DOUBLE);
    EXPECT_EQ(*static_cast<const double*>(t->data()), 1.0);
    EXPECT_EQ(in->spec().get_string_attribute("dhdr:animation"), "0");
    const OIIO::ParamValue* fps = in->spec().find_attribute("dhdr:fps");
    ASSERT_NE(fps, nullptr);
    EXPECT_EQ(*static_cast<const double*>(fps->data()), 2.0);
    // A still scene's probes record no moment.
    auto still = OIIO::ImageInput::open(path("baked2.probes.exr"));
    ASSERT_TRUE(still);
    EXPECT_EQ(still->spec().find_attribute("dhdr:animationTime"), nullptr);
    // The moments differ, so the probes differ: the panel moved.
    auto a = OIIO::ImageInput::open(path("seq.1.probes.exr"));
    std::vector<float> p1(a->spec().image_pixels() * 3), p2(p1.size());
    ASSERT_TRUE(a->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, p1.data()));
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, p2.data()));
    EXPECT_NE(p1, p2);
}

// Without --lights the scene lights its probes itself: its punctual lights and its glowing
// meshes are where the animation puts them at the frame's time, as in the file with the frame
// baked in.
TEST_F(ProbeFrames, TheScenesOwnLightsMoveWithIt) {
    // The panel glows, and a lamp hangs 0.5 units in front of it (its local +Z is the world's −X).
    auto withLights = [](nlohmann::json doc) { return withGlowAndLamp(std::move(doc), 0.5f); };
    writeJson(path("lamps.gltf"), withLights(nlohmann::json::parse(slurp(path("anim.gltf")))));
    writeJson(path("lamps_baked.gltf"),
              withLights(nlohmann::json::parse(slurp(path("baked2.gltf")))));
    const std::string opts = " --max-probes 200 --rays 64 --shadow-samples 2 -o ";
    const Result r = run("dhdr-probes " + path("lamps.gltf") + " --fps 2 --frames 1-2" + opts +
                         path("lamps.#.exr") + " -v");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("2 lights"), std::string::npos) << r.err; // the lamp and the panel
    ASSERT_EQ(
        run("dhdr-probes " + path("lamps_baked.gltf") + opts + path("lamps_baked.exr")).status, 0);
    expectSameProbes("lamps.2.exr", "lamps_baked.exr", kInstanced);
    // Lights files a frame (dhdr-gbuffer --lights-out's): each frame bakes under its own.
    ASSERT_EQ(run("dhdr-gbuffer " + path("lamps.gltf") + " --size 8x8 --fps 2 --frames 1-2 -o " +
                  path("lg.#.exr") + " --lights-out " + path("lamp.#.json"))
                  .status,
              0);
    ASSERT_EQ(run("dhdr-probes " + path("lamps.gltf") + " --fps 2 --frames 1-2 --lights " +
                  path("lamp.#.json") + opts + path("framed.#.exr"))
                  .status,
              0);
    for (const char* lights : {"lamp.2.json", "lamp.1.json"})
        ASSERT_EQ(run("dhdr-probes " + path("lamps.gltf") + " --fps 2 --frame 2 --lights " +
                      path(lights) + opts + path(std::string("with_") + lights + ".exr"))
                      .status,
                  0);
    expectSameProbes("framed.2.exr", "with_lamp.2.json.exr");
    const ImageBuf framed = read("framed.2.exr"), stale = read("with_lamp.1.json.exr");
    EXPECT_NE(
        std::memcmp(framed.localpixels(), stale.localpixels(),
                    framed.spec().image_pixels() * size_t(framed.nchannels()) * sizeof(float)),
        0); // frame 1's lamp stood 1.25 units away
}

// Frames before the first key and after the last hold the end poses (glTF 2.0, Appendix C):
// the static files at x = −2.5 and 2.5; an animated file baked without --frame or --time is
// frame 0, as dhdr-gbuffer renders it.
TEST_F(ProbeFrames, FramesOutsideTheAnimationHoldItsEnds) {
    ASSERT_EQ(bake("anim.gltf", "late.probes.exr", "--fps 2 --frame 10").status, 0);
    ASSERT_EQ(bake("baked_end.gltf", "end.probes.exr").status, 0);
    expectSameProbes("late.probes.exr", "end.probes.exr", kInstanced);
    ASSERT_EQ(bake("anim.gltf", "early.probes.exr", "--fps 2 --frame -1").status, 0);
    ASSERT_EQ(bake("baked_start.gltf", "start.probes.exr").status, 0);
    expectSameProbes("early.probes.exr", "start.probes.exr", kInstanced);
    ASSERT_EQ(bake("anim.gltf", "default.probes.exr").status, 0);
    expectSameProbes("default.probes.exr", "start.probes.exr", kInstanced);
}

// dhdr-light --probes with a frame pattern lights each G-buffer with its own frame's probes:
// the same bits as lighting it alone with that file. Where the panel stood at frame 1 (floor
// in front of x = −1.25), frame 1's probes bring more of its bounce light than frame 2's,
// where it has moved 1.25 units away. One file for the sequence is a static set: frame 1's
// probes light both frames.
TEST_F(ProbeFrames, DhdrLightTakesEachFramesOwnProbes) {
    ASSERT_EQ(run("dhdr-gbuffer " + path("anim.gltf") + " --size 64x64 --fps 2 --frames 1-2 -o " +
                  path("g.#.exr"))
                  .status,
              0);
    ASSERT_EQ(bake("anim.gltf", "p.#.exr", "--fps 2 --frames 1-2").status, 0);
    const std::string light = "dhdr-light --scene " + path("anim.gltf") + " --lights " +
                              path("sun.lights.json") + " --aovs --type float ";
    const Result seq = run(light + path("g.#.exr") + " --probes " + path("p.#.exr") + " -o " +
                           path("lit.#.exr") + " -v");
    ASSERT_EQ(seq.status, 0) << seq.err;
    EXPECT_EQ(seq.err.find("warning"), std::string::npos) << seq.err;
    for (const char* f : {"1", "2"}) {
        const std::string n = f;
        ASSERT_EQ(run(light + path("g." + n + ".exr") + " --probes " + path("p." + n + ".exr") +
                      " -o " + path("alone." + n + ".exr"))
                      .status,
                  0);
        EXPECT_TRUE(sameBits(read("lit." + n + ".exr"), read("alone." + n + ".exr"))) << f;
    }
    // Floor columns 4–11: x from −1.75 to −1.3, in front of the panel's frame-1 place.
    const ImageBuf lit1 = read("lit.1.exr"), lit2 = read("lit.2.exr");
    const double near = indirect(lit1, 4, 12), far = indirect(lit2, 4, 12);
    EXPECT_GT(near, 3.0 * far) << near << " " << far; // measured: 0.200 and 0.028
    // A static set: one file for both frames, frame 1's; no warning, -v says what it is.
    const Result set = run(light + path("g.#.exr") + " --probes " + path("p.1.exr") + " -o " +
                           path("set.#.exr") + " -v");
    ASSERT_EQ(set.status, 0) << set.err;
    EXPECT_EQ(set.err.find("warning"), std::string::npos) << set.err;
    EXPECT_NE(set.err.find("one probe file for every frame"), std::string::npos) << set.err;
    EXPECT_TRUE(sameBits(read("set.1.exr"), lit1));
    const ImageBuf set2 = read("set.2.exr");
    EXPECT_FALSE(sameBits(set2, lit2));
    // The floor there did not move; the rays that settle the probes' visibility where their
    // distance moments spread (docs/gi.md "Shading") see frame 2's scene, the panel gone.
    EXPECT_NEAR(indirect(set2, 4, 12), indirect(lit1, 4, 12), 0.1 * indirect(lit1, 4, 12));
}

// A frame whose probe file is missing fails, naming the file, with no output of its own (the
// other frames are lit: frames are independent); a probe file baked at another moment than
// its G-buffer shows is a warning naming both.
TEST_F(ProbeFrames, MissingAndMismatchedProbeFilesAreClear) {
    ASSERT_EQ(run("dhdr-gbuffer " + path("anim.gltf") + " --size 32x32 --fps 2 --frames 1-2 -o " +
                  path("m.#.gbuf.exr"))
                  .status,
              0);
    ASSERT_EQ(bake("anim.gltf", "m.#.probes.exr", "--fps 2 --frames 1-1").status, 0);
    const std::string light =
        "dhdr-light --lights " + path("sun.lights.json") + " --scene " + path("anim.gltf") + " ";
    const Result missing = run(light + path("m.#.gbuf.exr") + " --probes " +
                               path("m.#.probes.exr") + " -o " + path("m.#.hdr.exr"));
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.err.find("m.2.probes.exr: no such file (the probes of frame 2"),
              std::string::npos)
        << missing.err;
    EXPECT_TRUE(fs::exists(path("m.1.hdr.exr")));
    EXPECT_FALSE(fs::exists(path("m.2.hdr.exr")));
    EXPECT_TRUE(noTemporaries());
    // Frame 1's probes under frame 2's name: lit, with a warning naming both moments.
    fs::copy_file(path("m.1.probes.exr"), path("m.2.probes.exr"));
    const Result other = run(light + path("m.#.gbuf.exr") + " --probes " + path("m.#.probes.exr") +
                             " -o " + path("o.#.hdr.exr"));
    EXPECT_EQ(other.status, 0) << other.err;
    EXPECT_NE(other.err.find("m.2.probes.exr: baked at 0.5 s (frame 1 at 2 fps, animation 0), "
                             "but " +
                             path("m.2.gbuf.exr") + " shows 1 s (frame 2 at 2 fps, animation 0)"),
              std::string::npos)
        << other.err;
    EXPECT_EQ(other.err.find("m.1.probes.exr"), std::string::npos) << other.err;
    // One G-buffer and one probe file: that frame's, checked the same way.
    const Result single = run(light + path("m.2.gbuf.exr") + " --probes " + path("m.1.probes.exr") +
                              " -o " + path("single.exr"));
    EXPECT_EQ(single.status, 0);
    EXPECT_NE(single.err.find("m.1.probes.exr: baked at 0.5 s"), std::string::npos) << single.err;
    // A pattern in --probes needs one in the output (a sequence), as any patterned input.
    const Result one = run(light + path("m.1.gbuf.exr") + " --probes " + path("m.#.probes.exr") +
                           " -o " + path("one.exr"));
    EXPECT_EQ(one.status, 2);
    EXPECT_FALSE(fs::exists(path("one.exr")));
}

// dhdr-probes' own mistakes and limits: --frame with a pattern, --frames without one, an
// unknown animation (listing the file's), a still scene with --frame (a warning; the bake is
// the scene's one pose).
TEST_F(ProbeFrames, BadOptionsAreClear) {
    Result r = bake("anim.gltf", "x.#.exr", "--frame 2");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--frame and --time make one frame into one file"), std::string::npos)
        << r.err;
    r = bake("anim.gltf", "x.exr", "--frames 1-2");
    EXPECT_EQ(r.status, 2) << r.err;
    r = bake("anim.gltf", "x.exr", "--frame 1 --time 2");
    EXPECT_EQ(r.status, 2) << r.err;
    r = bake("anim.gltf", "x.exr", "--animation walk");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("anim.gltf: no animation 'walk' (the file has: 0 'anim0')"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
    r = bake("baked1.gltf", "still.#.exr", "--frames 1-2 --fps 2 -v");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("the last frame's bake (a still scene)"), std::string::npos) << r.err;
    expectSameProbes("still.1.exr", "still.2.exr");
    ASSERT_EQ(bake("baked1.gltf", "baked1.probes.exr").status, 0);
    expectSameProbes("still.1.exr", "baked1.probes.exr");
    r = bake("baked1.gltf", "still_frame.exr", "--frame 3");
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.err.find("the scene has no animation"), std::string::npos) << r.err;
    EXPECT_TRUE(noTemporaries());
}

// The timing options come from one place: dhdr-gbuffer and dhdr-probes explain them in the
// same words.
TEST_F(ProbeFrames, GBufferAndProbesShareTheirTimingOptions) {
    auto helpOf = [&](const std::string& tool, const std::string& option) {
        const Result r = run(tool + " --help");
        EXPECT_EQ(r.status, 0);
        const std::string text = r.out + r.err;
        const size_t at = text.find("\n  " + option + " ");
        EXPECT_NE(at, std::string::npos) << tool << " " << option;
        const size_t end = text.find("\n  -", at + 1);
        return text.substr(at, end - at);
    };
    for (const char* option : {"--frame", "--time", "--fps", "--animation"}) {
        const std::string a = helpOf("dhdr-gbuffer", option), b = helpOf("dhdr-probes", option);
        EXPECT_FALSE(a.empty());
        EXPECT_EQ(a, b) << option;
    }
}
