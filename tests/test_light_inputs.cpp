// The files dhdr-light, dhdr-ibl and dhdr-probes read besides the G-buffer, made hostile as
// another program (or a damaged disk) could make them: each is a clear error naming the file,
// exit 1, and no output; or, where the file is valid but unusual, the right picture.
#include "tool_test.h"

#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <cstring>
#include <fstream>
#include <functional>

using namespace dhdr::test;

namespace {

const std::string kCornell = kTestdata + "/cornell_box.gltf";
const std::string kGlass = kTestdata + "/cornell_glass.gltf";
const std::string kLights = kTestdata + "/cornell_box.lights.json";

class LightInputs : public ToolTest {
protected:
    static void SetUpTestSuite() {
        makeScratch();
        sharedInputs([] {
            ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 24x24 -o " + path("g.exr")).status,
                      0);
        });
    }

    static void write(const std::string& name, const std::string& text) {
        std::ofstream(path(name)) << text;
    }

    // A 64×32 environment of `channels` channels named `names`, every texel `value`.
    static void environment(const std::string& name, const std::vector<std::string>& names,
                            const std::vector<float>& value) {
        OIIO::ImageSpec spec(64, 32, int(names.size()), OIIO::TypeDesc::FLOAT);
        spec.channelnames = names;
        spec.alpha_channel = -1;
        OIIO::ImageBuf img(spec);
        OIIO::ImageBufAlgo::fill(img, value);
        ASSERT_TRUE(img.write(path(name)));
    }

    // Copies the multi-part file `from` to `to` as float, through `edit` of its parts' specs
    // and pixels: a file as dhdr wrote it but for the damage `edit` does.
    using Parts = std::vector<OIIO::ImageSpec>;
    using Pixels = std::vector<std::vector<float>>;
    static void rewrite(const std::string& from, const std::string& to,
                        const std::function<void(Parts&, Pixels&)>& edit) {
        auto in = OIIO::ImageInput::open(path(from));
        ASSERT_TRUE(in);
        Parts specs;
        Pixels pixels;
        for (int s = 0; in->seek_subimage(s, 0); ++s) {
            specs.push_back(in->spec());
            pixels.emplace_back(specs.back().image_pixels() * size_t(specs.back().nchannels));
            ASSERT_TRUE(in->read_image(s, 0, 0, specs.back().nchannels, OIIO::TypeDesc::FLOAT,
                                       pixels.back().data()));
        }
        edit(specs, pixels);
        for (OIIO::ImageSpec& s : specs) {
            s.format = OIIO::TypeDesc::FLOAT;
            s.channelformats.clear();
        }
        auto out = OIIO::ImageOutput::create(path(to));
        ASSERT_TRUE(out->open(path(to), int(specs.size()), specs.data()));
        for (size_t s = 0; s < specs.size(); ++s) {
            if (s > 0) {
                ASSERT_TRUE(out->open(path(to), specs[s], OIIO::ImageOutput::AppendSubimage));
            }
            ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels[s].data()));
        }
        ASSERT_TRUE(out->close());
    }

    // Runs dhdr-light on the G-buffer with the lights file `lights`; expects a failure that
    // names `names` and leaves no output.
    static void expectLightFails(const std::string& lights, const std::string& names,
                                 const std::string& extra = "") {
        const Result r = run("dhdr-light " + path("g.exr") + " --lights " + path(lights) + " " +
                             extra + " -o " + path("out.exr"));
        EXPECT_EQ(r.status, 1) << r.err;
        EXPECT_NE(r.err.find(names), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("out.exr")));
        EXPECT_TRUE(noTemporaries());
    }
};

} // namespace

// A luminance environment with alpha (Y, A) is grey: its alpha is not blue. Lit by it, a
// white-ish wall's R, G and B keep the wall's own colour ratios, as with an RGB grey sky.
TEST_F(LightInputs, LuminanceEnvironmentIsGrey) {
    environment("ya.exr", {"Y", "A"}, {0.5f, 1.0f});
    environment("rgb.exr", {"R", "G", "B"}, {0.5f, 0.5f, 0.5f});
    write("ya.json", R"({"lights": [{"type": "environment", "image": "ya.exr"}]})");
    write("rgb.json", R"({"lights": [{"type": "environment", "image": "rgb.exr"}]})");
    for (const char* name : {"ya", "rgb"}) {
        const Result r =
            run("dhdr-light " + path("g.exr") + " --lights " + path(std::string(name) + ".json") +
                " --type float -o " + path(std::string(name) + ".exr.out.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
    }
    const ImageBuf ya = read("ya.exr.out.exr"), rgb = read("rgb.exr.out.exr");
    const auto cmp = OIIO::ImageBufAlgo::compare(ya, rgb, 1e-5f, 1e-5f);
    EXPECT_EQ(cmp.nfail, 0u) << "max error " << cmp.maxerror;
}

// A header that claims 65536 × 32768 texels is refused before anything is allocated, by the
// lighting pass and by the bake alike.
TEST_F(LightInputs, OversizedEnvironmentIsRefusedBeforeReading) {
    environment("small.exr", {"R", "G", "B"}, {1.0f, 1.0f, 1.0f});
    std::string bytes;
    {
        std::ifstream in(path("small.exr"), std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    for (const char* name : {"dataWindow", "displayWindow"}) {
        const std::string key = std::string(name) + '\0' + "box2i" + '\0';
        const size_t at = bytes.find(key);
        ASSERT_NE(at, std::string::npos);
        const int box[4] = {0, 0, 65535, 32767};
        std::memcpy(&bytes[at + key.size() + 4], box, sizeof box);
    }
    bytes.append(size_t(32768) * 8, '\0'); // room for the line offset table it claims
    std::ofstream(path("huge.exr"), std::ios::binary) << bytes;
    write("huge.json", R"({"lights": [{"type": "environment", "image": "huge.exr"}]})");
    expectLightFails("huge.json", "65536x32768");
    const Result r = run("dhdr-ibl " + path("huge.exr") + " -o " + path("huge.ibl.exr"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("larger than an environment may be"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("huge.ibl.exr")));
}

// A baked IBL whose numbers are damaged (NaN in a level, then in its spherical harmonics) is an
// error naming what, not a black frame with exit 0.
TEST_F(LightInputs, NonFiniteNumbersInABakedIblAreAnError) {
    environment("sky.exr", {"R", "G", "B"}, {0.3f, 0.4f, 0.5f});
    ASSERT_EQ(run("dhdr-ibl " + path("sky.exr") + " --base-width 32 --samples 16 -o " +
                  path("sky.ibl.exr"))
                  .status,
              0);
    // Level 1 with one NaN texel, the rest of the file as dhdr-ibl wrote it.
    rewrite("sky.ibl.exr", "nan.ibl.exr", [](Parts& specs, Pixels& pixels) {
        ASSERT_GE(specs.size(), 3u);
        pixels[1][5] = NAN;
    });
    write("nan.json", R"({"lights": [{"type": "environment", "image": "nan.ibl.exr"}]})");
    expectLightFails("nan.json", "not finite");
}

// A deep G-buffer through --channels (which reads flat passes) and --deep-out with --channels
// are errors, not a crash and not an option silently ignored.
TEST_F(LightInputs, ChannelMapsReadFlatPassesOnly) {
    ASSERT_EQ(run("dhdr-gbuffer " + kGlass + " --size 24x24 -o " + path("deep.exr")).status, 0);
    write("map.json", R"({"depth": {"channels": ["Z"]},
        "position": {"channels": ["P.X", "P.Y", "P.Z"]},
        "normal": {"channels": ["N.X", "N.Y", "N.Z"]}, "coverage": {"channels": ["A"]}})");
    Result r = run("dhdr-light " + path("deep.exr") + " --channels " + path("map.json") +
                   " --camera-from " + kGlass + " --lights " + kLights + " -o " + path("m.exr"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("deep"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("m.exr")));
    r = run("dhdr-light " + path("g.exr") + " --channels " + path("map.json") + " --camera-from " +
            kCornell + " --lights " + kLights + " --deep-out " + path("md.exr") + " -o " +
            path("m.exr"));
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("--deep-out"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("m.exr")));
    EXPECT_FALSE(fs::exists(path("md.exr")));
}

// A spacing so small that the grid's count overflows an int was cut to one probe; it is an
// error naming the axis. A probe file whose positions are not finite is refused.
TEST_F(LightInputs, ProbeGridsOutOfRangeAreErrors) {
    Result r = run("dhdr-probes " + kCornell + " --spacing 1e-300 -o " + path("p.exr"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("probes along"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("p.exr")));
    ASSERT_EQ(run("dhdr-probes " + kCornell + " --grid 2,2,2 --rays 16 -o " + path("p.exr")).status,
              0);
    // Every position NaN, the rest of the file as written.
    rewrite("p.exr", "nan.probes.exr", [](Parts& specs, Pixels&) {
        const OIIO::ParamValue* pos = specs[0].find_attribute("dhdr:probePositions");
        ASSERT_TRUE(pos);
        const OIIO::TypeDesc type = pos->type();
        const std::vector<float> nan(size_t(type.arraylen), NAN);
        specs[0].attribute("dhdr:probePositions", type, nan.data());
    });
    r = run("dhdr-light " + path("g.exr") + " --scene " + kCornell + " --lights " + kLights +
            " --probes " + path("nan.probes.exr") + " -o " + path("out.exr"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("not finite"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("out.exr")));
}

// A probe file whose bias is NaN moved every shading point to NaN: indirect light 0 everywhere,
// exit 0. It is refused, naming the file and the attribute.
TEST_F(LightInputs, ProbeBiasesThatAreNotNumbersAreRefused) {
    ASSERT_EQ(
        run("dhdr-probes " + kCornell + " --grid 2,2,2 --rays 16 -o " + path("pb.exr")).status, 0);
    rewrite("pb.exr", "nanbias.probes.exr",
            [](Parts& specs, Pixels&) { specs[0].attribute("dhdr:probeNormalBias", NAN); });
    const Result r =
        run("dhdr-light " + path("g.exr") + " --scene " + kCornell + " --lights " + kLights +
            " --probes " + path("nanbias.probes.exr") + " -o " + path("out.exr"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("nanbias.probes.exr"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("dhdr:probeNormalBias"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("out.exr")));
}

// A 2x1 environment is twice as wide as it is high: its refusal says the real reason, a minimum
// size, not a shape it has.
TEST_F(LightInputs, AOneRowEnvironmentIsRefusedForItsSize) {
    OIIO::ImageBuf img(OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::FLOAT));
    OIIO::ImageBufAlgo::fill(img, {1.0f, 1.0f, 1.0f});
    ASSERT_TRUE(img.write(path("tiny.exr")));
    write("tiny.json", R"({"lights": [{"type": "environment", "image": "tiny.exr"}]})");
    expectLightFails("tiny.json", "at least 4x2");
    const Result r = run("dhdr-light " + path("g.exr") + " --lights " + path("tiny.json") + " -o " +
                         path("out.exr"));
    EXPECT_EQ(r.err.find("twice as wide"), std::string::npos) << r.err;
}

// -v says a raw environment is baked on reading, and not of a file dhdr-ibl baked.
TEST_F(LightInputs, OnlyARawEnvironmentIsSaidToBeBakedOnReading) {
    environment("raw.exr", {"R", "G", "B"}, {0.3f, 0.4f, 0.5f});
    ASSERT_EQ(run("dhdr-ibl " + path("raw.exr") + " --base-width 32 --samples 16 -o " +
                  path("raw.ibl.exr"))
                  .status,
              0);
    write("raw.json", R"({"lights": [{"type": "environment", "image": "raw.exr"}]})");
    write("baked.json", R"({"lights": [{"type": "environment", "image": "raw.ibl.exr"}]})");
    const std::string raw = "a raw image is baked on reading";
    Result r = run("dhdr-light " + path("g.exr") + " --lights " + path("raw.json") + " -v -o " +
                   path("raw.out.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE((r.out + r.err).find(raw), std::string::npos) << r.out << r.err;
    r = run("dhdr-light " + path("g.exr") + " --lights " + path("baked.json") + " -v -o " +
            path("baked.out.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ((r.out + r.err).find(raw), std::string::npos) << r.out << r.err;
    EXPECT_NE((r.out + r.err).find("baked by dhdr-ibl"), std::string::npos) << r.out << r.err;
}

// The G-buffer's header goes into the lit frame: a NaN dhdr:animationTime is refused (with or
// without --scene), not written on. A scene SHA-1 that tells nothing is a warning.
TEST_F(LightInputs, AMalformedGBufferRecordIsRefusedOrWarnedAbout) {
    rewrite("g.exr", "nantime.exr", [](Parts& specs, Pixels&) {
        const double nan = NAN;
        specs[0].attribute("dhdr:animationTime", OIIO::TypeDesc::DOUBLE, &nan);
    });
    Result r = run("dhdr-light " + path("nantime.exr") + " --lights " + kLights + " -o " +
                   path("out.exr"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("nantime.exr"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("dhdr:animationTime"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("out.exr")));
    // OpenImageIO drops an empty string on writing: a value that is no SHA-1, and the SHA-1 of
    // no bytes (what an empty or unreadable scene file gives), tell nothing either.
    const std::pair<const char*, const char*> records[] = {
        {"none", "is not a SHA-1"},
        {"DA39A3EE5E6B4B0D3255BFEF95601890AFD80709", "the SHA-1 of no bytes"}};
    for (const auto& [sha, says] : records) {
        rewrite("g.exr", "nosha.exr",
                [sha = sha](Parts& specs, Pixels&) { specs[0].attribute("dhdr:sceneSHA1", sha); });
        r = run("dhdr-light --gi direct " + path("nosha.exr") + " --scene " + kCornell +
                " --lights " + kLights + " -o " + path("out.exr"));
        EXPECT_EQ(r.status, 0) << r.err;
        EXPECT_NE(r.err.find(says), std::string::npos) << sha << ": " << r.err;
        fs::remove(path("out.exr"));
    }
}
