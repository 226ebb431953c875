// Inputs at the edges of what the tools take (issue 48), run as a user runs the tools: suns
// as wide as a lights file allows over an animated scene, lights and scenes past float's
// range in a probe bake, and dhdr-tonemap --scan's list file.
#include "animation_writer.h"
#include "tool_test.h"

#include <OpenImageIO/imageio.h>
#include <fstream>

using namespace dhdr::test;

namespace {

const std::string kAnimated = kTestdata + "/cornell_animated.gltf";
const std::string kCornell = kTestdata + "/cornell_box.gltf";

class ExtremeInputs : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    // `args` under `timeout`: a run that hangs fails the test (status 124) instead of the suite.
    static Result runWithin(int seconds, const std::string& args) {
        Result r;
        const std::string cmd = "timeout " + std::to_string(seconds) + " env -u OCIO " + kTools +
                                "/" + args + " >" + path("stdout.txt") + " 2>" +
                                path("stderr.txt") + " </dev/null";
        const int raw = std::system(cmd.c_str());
        r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
        r.err = slurp(dir / "stderr.txt");
        return r;
    }

    static void writeSun(const std::string& name, const std::string& angle,
                         const std::string& intensity = "3") {
        std::ofstream(path(name)) << R"({"lights": [{"type": "directional", "direction": )"
                                     R"([0.3, -1, -0.2], "intensity": )"
                                  << intensity << R"(, "angle": )" << angle << "}]}";
    }

    // Every value of both parts of a probe file, and how many are not finite.
    static long long nonFiniteProbeValues(const std::string& file) {
        auto in = OIIO::ImageInput::open(file);
        EXPECT_TRUE(in) << file;
        if (!in) return -1;
        long long bad = 0;
        for (int part = 0; part < 2; ++part) {
            EXPECT_TRUE(in->seek_subimage(part, 0));
            const OIIO::ImageSpec& s = in->spec();
            std::vector<float> v(s.image_pixels() * size_t(s.nchannels));
            EXPECT_TRUE(in->read_image(part, 0, 0, s.nchannels, OIIO::TypeDesc::FLOAT, v.data()));
            for (const float x : v)
                bad += !std::isfinite(x);
        }
        return bad;
    }
};

// A sun of angle 90° or 179° over a scene whose movers are Embree instances hung in 7 of 8
// runs on two threads (Embree's coherent packets of wide cones through instances never
// returned). Each run takes well under a second; several runs, each under `timeout`.
TEST_F(ExtremeInputs, AWideSunOverAnAnimatedSceneDoesNotHang) {
    ASSERT_EQ(run("dhdr-gbuffer " + kAnimated + " --size 64x64 --frames 12-12 -o " +
                  path("anim.####.exr"))
                  .status,
              0);
    for (const char* angle : {"90", "179"}) {
        writeSun(std::string("sun") + angle + ".json", angle);
        for (int i = 0; i < 4; ++i) {
            const Result r =
                runWithin(60, "dhdr-light --gi direct " + path("anim.0012.exr") + " --scene " +
                                  kAnimated + " --lights " + path("sun") + angle +
                                  ".json --threads 2 -o " + path("lit.exr"));
            ASSERT_EQ(r.status, 0) << "angle " << angle << ", run " << i << ": " << r.err;
        }
    }
}

// Lights of intensity 3·10³⁸ wrote 2,592 non-finite probe values with exit 0, and dhdr-light
// refused the bake. No finite irradiance would state such light: the bake is refused, and
// writes nothing.
TEST_F(ExtremeInputs, ProbesOfLightsPastFloatsRangeAreRefused) {
    std::ofstream(path("bright.json"))
        << R"({"lights": [{"type": "point", "position": [0.278, 0.45, 0.28], "intensity": 3e38},
                          {"type": "directional", "direction": [0.3, -1, -0.2],
                           "intensity": 3e38}]})";
    const Result r = runWithin(120, "dhdr-probes " + kCornell + " --lights " + path("bright.json") +
                                        " --grid 2,2,2 --rays 64 -o " + path("bright.probes.exr"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("the light reaching the probes is past float's range"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("bright.probes.exr")));
}

// A node scaled by 3·10³⁸ (its squared distances overflow float) wrote non-finite
// `meanSquare` values at every frame of --frames with exit 0.
TEST_F(ExtremeInputs, ProbesOfAScenePastFloatsRangeAreFinite) {
    nlohmann::json doc = squareAndCamera();
    doc["nodes"][0]["scale"] = {3e38, 3e38, 1.0};
    addChannel(doc, 0, 0, "translation", {0.0f, 1.0f}, {0, 0, 0, 0, 0, 1});
    writeJson(path("huge.gltf"), doc);
    writeSun("sun.json", "0");
    const Result r =
        runWithin(120, "dhdr-probes " + path("huge.gltf") + " --lights " + path("sun.json") +
                           " --grid 2,2,2 --rays 64 --frames 1-2 "
                           "-o " +
                           path("huge.####.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("distance moments past float's range"), std::string::npos) << r.err;
    for (const char* f : {"huge.0001.exr", "huge.0002.exr"})
        EXPECT_EQ(nonFiniteProbeValues(path(f)), 0) << f;
}

// dhdr-farm's scan of 30,000 chunks named every metering file on one command line, past
// ARG_MAX; --scan-list reads them from a file. A list that cannot be read is an error.
TEST_F(ExtremeInputs, ScanListIsReadOrRefused) {
    EXPECT_EQ(run("dhdr-tonemap --scan --scan-list " + path("none.txt") + " --stats-out " +
                  path("a.json"))
                  .status,
              1);
    EXPECT_NE(slurp(dir / "stderr.txt").find("none.txt: cannot be read"), std::string::npos);
    EXPECT_EQ(
        run("dhdr-tonemap --scan-list " + path("none.txt") + " x.exr -o " + path("x.png")).status,
        2);
    EXPECT_FALSE(fs::exists(path("a.json")));
}

// Under a capped address space (ulimit -v), --threads 128 made OpenImageIO's pool throw and
// keep empty slots: "Resource temporarily unavailable", then SIGSEGV at exit. Fewer threads
// run, or the error says why; never a signal.
TEST_F(ExtremeInputs, ThreadsThatCannotStartAreNoCrash) {
    ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 256x1024 -o " + path("tall.exr")).status,
              0);
    const std::string cmd = "ulimit -v 1000000; exec timeout 60 " + kTools + "/dhdr-light " +
                            path("tall.exr") + " --lights " + kTestdata +
                            "/cornell_box.lights.json --threads 128 -o " + path("tall.hdr.exr") +
                            " 2>" + path("threads.err") + " </dev/null";
    const int raw = std::system(("sh -c '" + cmd + "'").c_str());
    ASSERT_TRUE(WIFEXITED(raw));
    const int status = WEXITSTATUS(raw);
    const std::string err = slurp(dir / "threads.err");
    EXPECT_TRUE(status == 0 || status == 1) << status << ": " << err;
    if (status == 1) EXPECT_NE(err.find("ulimit -v"), std::string::npos) << err;
    EXPECT_EQ(fs::exists(path("tall.hdr.exr")), status == 0);
}

// `dhdr-light --gi path --spp 65536` at 1080p showed no progress for 20 s: the line moved once a
// strip. It now counts pixels as they are shaded; on a terminal (script(1) gives it one) a
// frame of one strip shows the percentages between 0 and 100, and its pixels are those of a
// run in a pipe.
TEST_F(ExtremeInputs, ProgressMovesWithinAStrip) {
    ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 64x48 -o " + path("p.exr")).status, 0);
    const std::string light = kTools + "/dhdr-light " + path("p.exr") + " --scene " + kCornell +
                              " --lights " + kTestdata +
                              "/cornell_box.lights.json --gi path --spp 16 -o ";
    const std::string tty = path("tty.txt");
    ASSERT_EQ(std::system(("timeout 120 script -qec '" + light + path("tty.exr") + "' /dev/null >" +
                           tty + " </dev/null")
                              .c_str()),
              0);
    const std::string shown = slurp(tty);
    for (const char* step : {"  1% (", " 50% (", " 99% (", "of 3072 pixels)", "done"})
        EXPECT_NE(shown.find(step), std::string::npos) << step << " in: " << shown;
    ASSERT_EQ(std::system((light + path("pipe.exr") + " 2>" + path("pipe.err") + " | cat").c_str()),
              0);
    EXPECT_EQ(slurp(dir / "pipe.err"), "");
    ImageBuf a(path("tty.exr")), b(path("pipe.exr"));
    ASSERT_TRUE(a.read() && b.read());
    const OIIO::ImageSpec& s = a.spec();
    std::vector<float> pa(s.image_pixels() * size_t(s.nchannels)), pb(pa.size());
    ASSERT_TRUE(a.get_pixels(a.roi(), OIIO::TypeDesc::FLOAT, pa.data()) &&
                b.get_pixels(b.roi(), OIIO::TypeDesc::FLOAT, pb.data()));
    EXPECT_EQ(pa, pb);
}

} // namespace
