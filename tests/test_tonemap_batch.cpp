// dhdr-tonemap's batch path (its PNG writer, png_writer.h) against OpenImageIO's
// (--png-writer oiio, the reference): the same chunks and the same stored pixels for
// sequences, every operator, adaptation split into processes, 16-bit, streamed frames; the
// same bytes for any number of threads; bad input named and no partial output.
#include "tool_test.h"

#include <OpenImageIO/imagebufalgo.h>
#include <random>

namespace dhdr::test {
namespace {

constexpr int kFrames = 4;

class ToneMapBatch : public ToolTest {
protected:
    // Noisy frames (a gradient times per-pixel Monte Carlo noise, a few fireflies), alpha
    // from 0 through partial to 1, half RGBA ZIP; 67×45 so that rows are odd-sized. Frame 3
    // on is four times brighter, so that adaptation has something to follow.
    static void SetUpTestSuite() {
        makeScratch();
        std::mt19937 rng(47);
        std::gamma_distribution<float> noise(4.0f, 0.25f);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        for (int f = 1; f <= kFrames; ++f) {
            OIIO::ImageSpec spec(67, 45, 4, OIIO::TypeDesc::HALF);
            spec.attribute("compression", "zip");
            ImageBuf frame(spec);
            for (int y = 0; y < 45; ++y)
                for (int x = 0; x < 67; ++x) {
                    const float n = noise(rng) * (unit(rng) < 0.01f ? 40.0f : 1.0f);
                    const float scale = f >= 3 ? 4.0f : 1.0f;
                    const float a = x < 5 ? 0.0f : x < 20 ? unit(rng) : 1.0f;
                    const float rgba[4] = {scale * n * (0.1f + 2.0f * x / 67.0f),
                                           scale * n * (0.2f + y / 45.0f), scale * n * 0.5f, a};
                    frame.setpixel(x, y, rgba);
                }
            ASSERT_TRUE(frame.write(path(name("in", f, ".exr"))));
        }
        const std::string bytes = slurp(dir / name("in", 2, ".exr"));
        fs::create_directories(dir / "bad");
        for (int f = 1; f <= 2; ++f)
            fs::copy_file(dir / name("in", f, ".exr"), dir / "bad" / name("in", f, ".exr"));
        std::ofstream(dir / "bad" / name("in", 2, ".exr"), std::ios::binary)
            .write(bytes.data(), std::streamsize(bytes.size() / 2));
    }

    static std::string name(const std::string& stem, int frame, const std::string& ext) {
        char text[64];
        std::snprintf(text, sizeof text, "%s.%04d%s", stem.c_str(), frame, ext.c_str());
        return text;
    }

    // The values as stored, in the file's own type: no association of alpha on the way in.
    static std::vector<unsigned char> stored(const std::string& file) {
        OIIO::ImageSpec config;
        config.attribute("oiio:UnassociatedAlpha", 1);
        auto in = OIIO::ImageInput::open(path(file), &config);
        if (!in) return {};
        std::vector<unsigned char> pixels(in->spec().image_bytes());
        if (!in->read_image(0, 0, 0, -1, in->spec().format, pixels.data())) return {};
        return pixels;
    }

    // A PNG up to its first IDAT's length: signature and the chunks before the pixels.
    static std::string header(const std::string& file) {
        const std::string bytes = slurp(dir / file);
        return bytes.substr(0, bytes.find("IDAT") - 4);
    }

    static void expectSame(const std::string& ours, const std::string& reference) {
        const std::vector<unsigned char> a = stored(ours), b = stored(reference);
        EXPECT_FALSE(a.empty()) << ours;
        EXPECT_TRUE(a == b) << ours << " and " << reference << " hold different pixels";
        if (reference.size() > 4 && reference.substr(reference.size() - 4) == ".png")
            EXPECT_EQ(header(ours), header(reference)) << ours;
    }

    static std::string in() { return " " + path("in.####.exr") + " "; }
};

TEST_F(ToneMapBatch, ASequenceHoldsOpenImageIOsPixelsAndChunks) {
    Result r = run("dhdr-tonemap" + in() + "--frames 1-4 -o " + path("seq.####.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("dhdr-tonemap" + in() + "--frames 1-4 --png-writer oiio -o " + path("ref.####.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    for (int f = 1; f <= kFrames; ++f) {
        expectSame(name("seq", f, ".png"), name("ref", f, ".png"));
        // Two writers: the same pixels, deflated differently.
        EXPECT_NE(slurp(dir / name("seq", f, ".png")), slurp(dir / name("ref", f, ".png")));
    }
    EXPECT_TRUE(noTemporaries());
}

TEST_F(ToneMapBatch, EveryOperatorAndFormHoldsOpenImageIOsPixels) {
    const std::string frame = path(name("in", 1, ".exr"));
    std::vector<std::string> options;
    for (const char* op : {"reinhard", "reinhard-local", "drago", "hable", "pbr-neutral", "agx",
                           "exposure", "aces", "none"})
        options.push_back(std::string("--op ") + op);
    // 16-bit, undithered, streamed strip by strip, one thread.
    for (const char* more : {"--bits 16", "--no-dither", "--memory 0", "--threads 1"})
        options.push_back(more);
    int i = 0;
    for (const std::string& o : options) {
        const std::string ours = "op" + std::to_string(i) + ".png";
        const std::string ref = "opref" + std::to_string(i++) + ".png";
        Result r = run("dhdr-tonemap " + frame + " " + o + " -o " + path(ours));
        ASSERT_EQ(r.status, 0) << o << ": " << r.err;
        r = run("dhdr-tonemap " + frame + " " + o + " --png-writer oiio -o " + path(ref));
        ASSERT_EQ(r.status, 0) << o << ": " << r.err;
        SCOPED_TRACE(o);
        expectSame(ours, ref);
    }
    // EXR output is OpenImageIO's either way.
    ASSERT_EQ(run("dhdr-tonemap " + frame + " -o " + path("op.exr")).status, 0);
    ASSERT_EQ(run("dhdr-tonemap " + frame + " --png-writer oiio -o " + path("opref.exr")).status,
              0);
    expectSame("op.exr", "opref.exr");
}

TEST_F(ToneMapBatch, AdaptationSplitIntoProcessesHoldsTheReferencesPixels) {
    Result r = run("dhdr-tonemap" + in() + "--frames 1-4 --adapt --png-writer oiio -o " +
                   path("adref.####.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("dhdr-tonemap" + in() + "--frames 1-4 --adapt -o " + path("ad.####.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    // dhdr-farm's chunks: metering in two, the scan, mapping in two (one streamed).
    for (const char* range : {"1-2", "3-4"})
        ASSERT_EQ(run("dhdr-tonemap" + in() + "--frames " + range + " --meter-only --stats-out " +
                      path(std::string("m") + range + ".json"))
                      .status,
                  0);
    ASSERT_EQ(run("dhdr-tonemap --scan " + path("m1-2.json") + " " + path("m3-4.json") +
                  " --stats-out " + path("adapted.json"))
                  .status,
              0);
    ASSERT_EQ(run("dhdr-tonemap" + in() + "--frames 1-2 --adapt-from " + path("adapted.json") +
                  " -o " + path("chunk.####.png"))
                  .status,
              0);
    ASSERT_EQ(run("dhdr-tonemap" + in() + "--frames 3-4 --memory 0 --adapt-from " +
                  path("adapted.json") + " -o " + path("chunk.####.png"))
                  .status,
              0);
    for (int f = 1; f <= kFrames; ++f) {
        SCOPED_TRACE(f);
        expectSame(name("ad", f, ".png"), name("adref", f, ".png"));
        expectSame(name("chunk", f, ".png"), name("adref", f, ".png"));
    }
}

TEST_F(ToneMapBatch, TheBytesDoNotDependOnTheThreads) {
    for (const char* threads : {"1", "2", "5"}) {
        const std::string t = threads;
        ASSERT_EQ(run("dhdr-tonemap" + in() + "--frames 1-4 --threads " + t + " -o " +
                      path("t" + t + ".####.png"))
                      .status,
                  0);
        ASSERT_EQ(run("dhdr-tonemap " + path(name("in", 1, ".exr")) + " --threads " + t + " -o " +
                      path("one" + t + ".png"))
                      .status,
                  0);
    }
    for (const char* threads : {"2", "5"}) {
        const std::string t = threads;
        EXPECT_EQ(slurp(dir / "one1.png"), slurp(dir / ("one" + t + ".png"))) << t;
        for (int f = 1; f <= kFrames; ++f)
            EXPECT_EQ(slurp(dir / name("t1", f, ".png")), slurp(dir / name("t" + t, f, ".png")))
                << t << " threads, frame " << f;
    }
}

TEST_F(ToneMapBatch, BadInputIsNamedAndLeavesNoPartialOutput) {
    const Result r = run("dhdr-tonemap " + path("bad/in.####.exr") + " --frames 1-2 -o " +
                         path("bad/out.####.png"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(path("bad/" + name("in", 2, ".exr"))), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "bad" / name("out", 2, ".png")));
    for (const auto& e : fs::directory_iterator(dir / "bad"))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
    // An output folder that does not exist: named, nothing written.
    const Result w =
        run("dhdr-tonemap " + path(name("in", 1, ".exr")) + " -o " + path("nowhere/out.png"));
    EXPECT_EQ(w.status, 1);
    EXPECT_NE(w.err.find(path("nowhere/out.png")), std::string::npos) << w.err;
}

} // namespace
} // namespace dhdr::test
