// The five executables as a user runs them: exit codes, messages, no partial output, thread
// independence. The fixture renders its inputs with the tools themselves.
#include "tool_test.h"

#include <OpenImageIO/imagebufalgo.h>

using namespace dhdr::test;

namespace {

class Tools : public ToolTest {
protected:
    static void SetUpTestSuite() {
        makeScratch();
        sharedInputs([] {
            ASSERT_EQ(run("dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --size 96x72 -o " +
                          path("g.exr"))
                          .status,
                      0);
            ASSERT_EQ(run("dhdr-light " + path("g.exr") + " --lights " + kTestdata +
                          "/cornell_box.lights.json --aovs --type float -o " + path("h.exr"))
                          .status,
                      0);
            // A truncated copy of the HDR frame.
            const std::string bytes = slurp(dir / "h.exr");
            std::ofstream(dir / "truncated.exr", std::ios::binary)
                .write(bytes.data(), std::streamsize(bytes.size() / 2));
            std::ofstream(dir / "bad_lights.json")
                << R"({"lights": [{"type": "point", "intensity": 1}]})";
        });
    }
    static bool samePixels(const std::string& a, const std::string& b) {
        const ImageBuf A = read(a), B = read(b);
        if (!A.initialized() || !B.initialized() ||
            A.spec().image_bytes() != B.spec().image_bytes())
            return false;
        return std::memcmp(A.localpixels(), B.localpixels(), A.spec().image_bytes()) == 0;
    }

    // Writes a float RGBA EXR with NaN and ±Inf pixels.
    static void writePoisoned(const std::string& name) {
        ImageBuf img(OIIO::ImageSpec(32, 16, 4, OIIO::TypeDesc::FLOAT));
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 32; ++x) {
                float* p = static_cast<float*>(img.pixeladdr(x, y));
                p[0] = p[1] = p[2] = 0.1f * float(x + 1);
                p[3] = 1.0f;
            }
        static_cast<float*>(img.pixeladdr(3, 3))[0] = NAN;
        static_cast<float*>(img.pixeladdr(4, 3))[1] = INFINITY;
        static_cast<float*>(img.pixeladdr(5, 3))[2] = -INFINITY;
        static_cast<float*>(img.pixeladdr(6, 3))[2] = -0.5f;
        img.write(path(name));
    }
};

const char* kAllTools[] = {"dhdr-gbuffer", "dhdr-light", "dhdr-tonemap", "dhdr-bloom", "dhdr-aa"};

} // namespace

TEST_F(Tools, HelpAndVersion) {
    for (const char* tool : kAllTools) {
        Result r = run(std::string(tool) + " --help");
        EXPECT_EQ(r.status, 0) << tool;
        EXPECT_NE(r.out.find("Usage: " + std::string(tool)), std::string::npos) << tool;
        EXPECT_NE(r.out.find("--threads"), std::string::npos) << tool;
        r = run(std::string(tool) + " --version");
        EXPECT_EQ(r.status, 0);
        EXPECT_NE(r.out.find("dhdr"), std::string::npos);
    }
}

TEST_F(Tools, UsageErrorsExitWithTwo) {
    for (const char* tool : kAllTools) {
        Result r = run(std::string(tool) + " --no-such-option");
        EXPECT_EQ(r.status, 2) << tool;
        EXPECT_NE(r.err.find("unknown option --no-such-option"), std::string::npos) << tool;
        r = run(std::string(tool) + " " + path("h.exr")); // no -o
        EXPECT_EQ(r.status, 2) << tool;
    }
}

TEST_F(Tools, MissingInputIsNamedAndLeavesNoOutput) {
    const std::string missing = path("nowhere.exr");
    const std::string out = path("missing_out.exr");
    const std::string commands[] = {
        "dhdr-gbuffer " + path("nowhere.gltf") + " -o " + out,
        "dhdr-light " + missing + " --lights " + kTestdata + "/cornell_box.lights.json -o " + out,
        "dhdr-tonemap " + missing + " -o " + out,
        "dhdr-bloom " + missing + " -o " + out,
        "dhdr-aa " + missing + " -o " + out,
    };
    for (const std::string& c : commands) {
        const Result r = run(c);
        EXPECT_EQ(r.status, 1) << c;
        EXPECT_NE(r.err.find("nowhere."), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out)) << c;
    }
}

TEST_F(Tools, TruncatedExrIsAnErrorAndLeavesNoOutput) {
    const std::string in = path("truncated.exr"), out = path("truncated_out.exr");
    for (const std::string tool : {"dhdr-tonemap", "dhdr-bloom", "dhdr-aa"}) {
        const Result r = run(tool + " " + in + " -o " + out);
        EXPECT_EQ(r.status, 1) << tool;
        EXPECT_NE(r.err.find("truncated.exr: cannot read"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
    // A G-buffer cut short: its header is whole, its pixels are not.
    const std::string bytes = slurp(dir / "g.exr");
    std::ofstream(dir / "truncated_g.exr", std::ios::binary)
        .write(bytes.data(), std::streamsize(bytes.size() / 2));
    const Result r = run("dhdr-light " + path("truncated_g.exr") + " --lights " + kTestdata +
                         "/cornell_box.lights.json -o " + out);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("truncated_g.exr: cannot read"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(noTemporaries());
}

TEST_F(Tools, MissingChannelIsNamed) {
    const std::string out = path("channel_out.exr");
    Result r = run("dhdr-light " + path("h.exr") + " --lights " + kTestdata +
                   "/cornell_box.lights.json -o " + out);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("h.exr: no channel 'P.X' — is this a G-buffer?"), std::string::npos)
        << r.err;
    ImageBuf grey(OIIO::ImageSpec(96, 72, 1, OIIO::TypeDesc::FLOAT));
    grey.write(path("grey.exr"));
    // Geometry without normals cannot drive normal-based edge AA.
    r = run("dhdr-aa " + path("h.exr") + " --use normal --gbuffer " + path("grey.exr") + " -o " +
            out);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("grey.exr: no channel 'N.X'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    for (const std::string tool : {"dhdr-tonemap", "dhdr-bloom"}) {
        r = run(tool + " " + path("grey.exr") + " -o " + path("grey_out.exr"));
        EXPECT_EQ(r.status, 1);
        EXPECT_NE(r.err.find("grey.exr: no R, G, B channels"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("grey_out.exr")));
    }
}

TEST_F(Tools, NonFinitePixelsAreReplacedAndReported) {
    writePoisoned("poisoned.exr");
    Result r = run("dhdr-tonemap " + path("poisoned.exr") + " -o " + path("poisoned.png"));
    EXPECT_EQ(r.status, 0) << r.err;
    // A display shows no negative light: the tone mapper counts negatives in the same line.
    EXPECT_NE(r.err.find("replaced 4 non-finite or negative values (1 NaN → 0, 1 +Inf → 65504, "
                         "1 -Inf → 0, 1 negative → 0)"),
              std::string::npos)
        << r.err;
    ImageBuf png = read("poisoned.png");
    ASSERT_TRUE(png.initialized());
    EXPECT_EQ(png.spec().width, 32);
    // A NaN in alpha as well: still one line, which counts it.
    ImageBuf alphaNan = read("poisoned.exr");
    static_cast<float*>(alphaNan.pixeladdr(7, 3))[3] = NAN;
    ASSERT_TRUE(alphaNan.write(path("poisoned_alpha.exr")));
    r = run("dhdr-tonemap " + path("poisoned_alpha.exr") + " -o " + path("poisoned_alpha.png"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("replaced 5 non-finite or negative values (2 NaN → 0"), std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("replaced"), r.err.rfind("replaced")) << r.err;
    r = run("dhdr-bloom " + path("poisoned.exr") + " -o " + path("poisoned_bloom.exr"));
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.err.find("replaced 3 non-finite values"), std::string::npos) << r.err;
    EXPECT_TRUE(allFinite(read("poisoned_bloom.exr")));
    r = run("dhdr-tonemap -q " + path("poisoned.exr") + " -o " + path("quiet.png"));
    EXPECT_EQ(r.status, 0);
    EXPECT_EQ(r.err, "");
}

TEST_F(Tools, MalformedLightsFileIsNamed) {
    const std::string out = path("lights_out.exr");
    Result r =
        run("dhdr-light " + path("g.exr") + " --lights " + path("bad_lights.json") + " -o " + out);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("bad_lights.json: light 0: \"position\" is required"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(out));
    std::ofstream(path("not_json.json")) << "{ lights: [";
    r = run("dhdr-light " + path("g.exr") + " --lights " + path("not_json.json") + " -o " + out);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("not_json.json: not valid JSON"), std::string::npos) << r.err;
}

TEST_F(Tools, UnwritableOutputFolder) {
    const std::string out = " -o /nonexistent-folder/out.exr";
    const std::string commands[] = {
        "dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --size 8x8" + out,
        "dhdr-light " + path("g.exr") + " --lights " + kTestdata + "/cornell_box.lights.json" + out,
        "dhdr-tonemap " + path("h.exr") + out,
        "dhdr-bloom " + path("h.exr") + out,
        "dhdr-aa " + path("h.exr") + out,
    };
    for (const std::string& c : commands) {
        const Result r = run(c);
        EXPECT_EQ(r.status, 1) << c;
        EXPECT_NE(r.err.find("/nonexistent-folder/out.exr: the folder /nonexistent-folder does "
                             "not exist"),
                  std::string::npos)
            << r.err;
    }
}

TEST_F(Tools, BrokenSceneIsAnErrorAndLeavesNoOutput) {
    const std::string scene = slurp(kTestdata + "/cornell_box.gltf");
    std::ofstream(dir / "truncated.gltf") << scene.substr(0, scene.size() / 2);
    const Result r = run("dhdr-gbuffer " + path("truncated.gltf") + " -o " + path("scene_out.exr"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("truncated.gltf: cannot load the scene"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("scene_out.exr")));
    Result look = run("dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --lookat 1,2,3 -o " +
                      path("scene_out.exr"));
    EXPECT_EQ(look.status, 2);
    EXPECT_NE(look.err.find("--lookat needs 6 or 9 numbers"), std::string::npos) << look.err;
    look = run("dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --size 16x16 --lookat " +
               "0.278,0.273,-0.8,0.278,0.273,0 -o " + path("lookat.exr"));
    EXPECT_EQ(look.status, 0) << look.err;
    const Result cam = run("dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --camera nope -o " +
                           path("scene_out.exr"));
    EXPECT_EQ(cam.status, 1);
    EXPECT_NE(cam.err.find("no camera named 'nope' (it has: camera)"), std::string::npos)
        << cam.err;
    EXPECT_FALSE(fs::exists(path("scene_out.exr")));
}

TEST_F(Tools, NonFiniteGBufferAndGeometryAreReplaced) {
    // A G-buffer with a NaN albedo and an infinite normal on covered pixels.
    ImageBuf g = read("g.exr");
    const int albedo = g.spec().channelindex("albedo.R"), normal = g.spec().channelindex("N.X");
    static_cast<float*>(g.pixeladdr(48, 36))[albedo] = NAN;
    static_cast<float*>(g.pixeladdr(50, 36))[normal] = INFINITY;
    ASSERT_TRUE(g.write(path("g_nan.exr")));
    Result r = run("dhdr-light " + path("g_nan.exr") + " --lights " + kTestdata +
                   "/cornell_box.lights.json --type float -o " + path("h_nan.exr"));
    EXPECT_EQ(r.status, 0) << r.err;
    // One line for the whole G-buffer: the NaN albedo and the infinite normal.
    EXPECT_NE(r.err.find("g_nan.exr: replaced 2 non-finite values (1 NaN → 0, 1 +Inf"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(allFinite(read("h_nan.exr")));
    // An HDR frame carrying its own N and Z (--aovs), with a NaN colour and an infinite normal.
    ImageBuf h = read("h.exr");
    static_cast<float*>(h.pixeladdr(48, 36))[0] = NAN;
    static_cast<float*>(h.pixeladdr(50, 36))[h.spec().channelindex("N.X")] = INFINITY;
    ASSERT_TRUE(h.write(path("h_poisoned.exr")));
    r = run("dhdr-aa " + path("h_poisoned.exr") + " -o " + path("aa_nan.exr"));
    EXPECT_EQ(r.status, 0) << r.err;
    // One line for the file, as dhdr-light gives for a G-buffer: the colour's NaN and the
    // normal's +Inf (the normal of a separate --gbuffer is that file's line).
    EXPECT_NE(r.err.find("h_poisoned.exr: replaced 2 non-finite values (1 NaN → 0, 1 +Inf"),
              std::string::npos)
        << r.err;
    const ImageBuf aa = read("aa_nan.exr");
    for (int y = 0; y < 72; ++y)
        for (int x = 0; x < 96; ++x)
            for (int c = 0; c < 4; ++c)
                ASSERT_TRUE(std::isfinite(static_cast<const float*>(aa.pixeladdr(x, y))[c]));
}

TEST_F(Tools, RefusesToOverwriteItsInput) {
    const auto before = fs::file_size(path("h.exr"));
    for (const std::string tool : {"dhdr-tonemap", "dhdr-bloom", "dhdr-aa"}) {
        const Result r = run(tool + " " + path("h.exr") + " -o " + path("h.exr"));
        EXPECT_EQ(r.status, 2) << tool;
        EXPECT_NE(r.err.find("is also an input"), std::string::npos) << r.err;
    }
    EXPECT_EQ(fs::file_size(path("h.exr")), before);
}

TEST_F(Tools, OutputDoesNotDependOnThreadCount) {
    const std::string lights = " --lights " + kTestdata + "/cornell_box.lights.json";
    const std::pair<std::string, std::string> jobs[] = {
        {"dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --size 96x72", "exr"},
        {"dhdr-light " + path("g.exr") + lights, "exr"},
        {"dhdr-tonemap " + path("h.exr"), "png"},
        {"dhdr-bloom " + path("h.exr"), "exr"},
        {"dhdr-aa " + path("h.exr") + " --gbuffer " + path("g.exr"), "exr"},
    };
    int i = 0;
    for (const auto& [command, ext] : jobs) {
        const std::string one = "t1_" + std::to_string(i) + "." + ext;
        const std::string two = "t2_" + std::to_string(i) + "." + ext;
        ASSERT_EQ(run(command + " --threads 1 -o " + path(one)).status, 0) << command;
        ASSERT_EQ(run(command + " --threads 2 -o " + path(two)).status, 0) << command;
        EXPECT_TRUE(samePixels(one, two)) << command;
        ++i;
    }
    EXPECT_TRUE(noTemporaries());
}

TEST_F(Tools, GBufferFileFollowsTheContract) {
    const ImageBuf g = read("g.exr");
    const OIIO::ImageSpec& spec = g.nativespec();
    for (const char* name : {"A", "Z", "P.X", "N.Z", "albedo.G", "roughness", "metallic",
                             "emission.R", "id.object", "id.material"})
        EXPECT_GE(spec.channelindex(name), 0) << name;
    EXPECT_EQ(spec.channelformat(spec.channelindex("Z")), OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(spec.channelformat(spec.channelindex("N.X")), OIIO::TypeDesc::HALF);
    EXPECT_EQ(spec.channelformat(spec.channelindex("id.object")), OIIO::TypeDesc::UINT);
    EXPECT_NE(spec.find_attribute("worldToCamera"), nullptr);
    EXPECT_NE(spec.find_attribute("worldToNDC"), nullptr);
    const OIIO::ParamValue* names = spec.find_attribute("dhdr:objectNames");
    ASSERT_NE(names, nullptr);
    EXPECT_EQ(names->type().numelements() * names->nvalues(), 9); // background + 8 objects
}

TEST_F(Tools, SceneLightsFlowIntoTheLightingStage) {
    const Result g =
        run("dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --size 48x48 --lights-out " +
            path("scene.lights.json") + " -o " + path("g48.exr"));
    ASSERT_EQ(g.status, 0) << g.err;
    const std::string text = slurp(dir / "scene.lights.json");
    EXPECT_NE(text.find("\"ceiling_light\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"spot\""), std::string::npos) << text;
    const Result l = run("dhdr-light " + path("g48.exr") + " --lights " +
                         path("scene.lights.json") + " -o " + path("h48.exr"));
    EXPECT_EQ(l.status, 0) << l.err;
}

TEST_F(Tools, CulledLightingEqualsBruteForce) {
    // The Cornell box's lights plus a fill, culled and brute force, compared pixel by pixel.
    const std::string lights = " --lights " + kTestdata + "/cornell_box.lights.json --lights " +
                               kTestdata + "/cornell_box.fill.lights.json --type float";
    ASSERT_EQ(run("dhdr-light " + path("g.exr") + lights + " -o " + path("culled.exr")).status, 0);
    ASSERT_EQ(run("dhdr-light " + path("g.exr") + lights + " --brute-force -o " + path("brute.exr"))
                  .status,
              0);
    const ImageBuf a = read("culled.exr"), b = read("brute.exr");
    ASSERT_EQ(a.spec().image_pixels(), b.spec().image_pixels());
    const float* pa = static_cast<const float*>(a.localpixels());
    const float* pb = static_cast<const float*>(b.localpixels());
    for (size_t i = 0; i < a.spec().image_pixels() * 4; ++i)
        ASSERT_NEAR(pa[i], pb[i], 1e-5 * std::max(1e-6f, std::abs(pb[i]))) << i;
}

TEST_F(Tools, ToneMapOperatorsAndMetadata) {
    for (const std::string op : {"reinhard", "reinhard-local", "drago", "hable", "pbr-neutral",
                                 "agx", "exposure", "aces"}) {
        const Result r = run("dhdr-tonemap " + path("h.exr") + " --op " + op + " -o " +
                             path("op_" + op + ".png"));
        ASSERT_EQ(r.status, 0) << op << ": " << r.err;
        const ImageBuf png = read("op_" + op + ".png");
        EXPECT_EQ(png.spec().get_string_attribute("dhdr:toneMap"), op);
        EXPECT_NE(png.spec().get_string_attribute("dhdr:toneMapParameters").find("key 0.18"),
                  std::string::npos);
        EXPECT_NE(png.spec().get_string_attribute("dhdr:source").find("h.exr"), std::string::npos);
        EXPECT_EQ(png.spec().get_string_attribute("dhdr:display"),
                  op == "aces" ? "sRGB / ACES (built-in config)"
                               : "sRGB / Standard (built-in config)");
        // Display-referred, whatever the input said: not the EXR's "Linear" (PNG's gAMA 1).
        EXPECT_EQ(png.spec().get_string_attribute("oiio:ColorSpace"), "sRGB");
    }
    const Result view = run("dhdr-tonemap " + path("h.exr") + " --view Filmic -o " + path("x.png"));
    EXPECT_EQ(view.status, 1);
    EXPECT_NE(view.err.find("unknown view 'Filmic' of display 'sRGB' (it has: Standard, ACES)"),
              std::string::npos)
        << view.err;
    const Result bad = run("dhdr-tonemap " + path("h.exr") + " --op aces9 -o " + path("x.png"));
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("--op: must be reinhard, "), std::string::npos) << bad.err;
    // Dithering is deterministic: the same input gives the same bytes' pixels.
    ASSERT_EQ(run("dhdr-tonemap " + path("h.exr") + " -o " + path("d1.png")).status, 0);
    ASSERT_EQ(run("dhdr-tonemap " + path("h.exr") + " --threads 1 -o " + path("d2.png")).status, 0);
    EXPECT_TRUE(samePixels("d1.png", "d2.png"));
}

TEST_F(Tools, SequenceAdaptationFollowsTheFormulaFrameByFrame) {
    // Eight grey frames: luminance 1, then a step to 16 at frame 4.
    fs::create_directories(dir / "seq");
    for (int f = 1; f <= 8; ++f) {
        ImageBuf frame(OIIO::ImageSpec(16, 8, 3, OIIO::TypeDesc::FLOAT));
        const float v = f < 4 ? 1.0f : 16.0f;
        const float grey[3] = {v, v, v};
        OIIO::ImageBufAlgo::fill(frame, grey);
        char name[64];
        std::snprintf(name, sizeof name, "seq/in.%04d.exr", f);
        ASSERT_TRUE(frame.write(path(name)));
    }
    const std::string common = "dhdr-tonemap " + path("seq/in.####.exr") + " --adapt --fps 30";
    Result r = run(common + " --stats-out " + path("seq/stats.json") + " -o " +
                   path("seq/one.%04d.png") + " --threads 1");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string json = slurp(dir / "seq/stats.json");
    // adapted₁ = L₁; adaptedᵢ = adaptedᵢ₋₁ + (Lᵢ − adaptedᵢ₋₁)(1 − 0.98^(30/30)), L = δ + Lw.
    double adapted = 1.0001;
    size_t at = 0;
    for (int f = 1; f <= 8; ++f) {
        const double L = f < 4 ? 1.0001 : 16.0001;
        if (f > 1) adapted += (L - adapted) * (1.0 - 0.98);
        at = json.find("\"frame\": " + std::to_string(f), at);
        ASSERT_NE(at, std::string::npos) << json;
        const size_t a = json.find("\"adapted\": ", at) + 11;
        EXPECT_NEAR(std::stod(json.substr(a)), adapted, 1e-6) << "frame " << f;
        const size_t l = json.find("\"logAverage\": ", at) + 14;
        EXPECT_NEAR(std::stod(json.substr(l)), L, 1e-6) << "frame " << f;
    }
    // Two threads map the same frames to the same pixels.
    r = run(common + " --threads 2 -o " + path("seq/two.####.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    for (int f = 1; f <= 8; ++f) {
        char one[64], two[64];
        std::snprintf(one, sizeof one, "seq/one.%04d.png", f);
        std::snprintf(two, sizeof two, "seq/two.%04d.png", f);
        EXPECT_TRUE(samePixels(one, two)) << f;
    }
    // Without --adapt, a frame of a sequence (one thread, strip after strip) is the same as
    // that file mapped on its own (strips computed while the previous one is encoded).
    r = run("dhdr-tonemap " + path("seq/in.####.exr") + " -o " + path("seq/plain.####.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("dhdr-tonemap " + path("seq/in.0005.exr") + " -o " + path("seq/alone.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(samePixels("seq/plain.0005.png", "seq/alone.png"));
    // A frame the range names but the folder lacks: an error, and with --adapt nothing written.
    r = run(common + " --frames 1-9 -o " + path("seq/miss.####.png"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("in.0009.exr: no such file"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("seq/miss.0001.png")));
    // Patterns on both sides or neither.
    r = run("dhdr-tonemap " + path("seq/in.####.exr") + " -o " + path("seq/single.png"));
    EXPECT_EQ(r.status, 2);
}

TEST_F(Tools, StreamedFramesMapLikeWholeOnes) {
    // --memory 0 streams the 96x72 frame in two strips (one pass per metering pass, one to
    // map); the default holds it whole. Every operator with both meterings, and every pair
    // of operator and output type and of metering and output type: the output type alternates
    // (png, exr) over the operator-metering pairs, so that each operator writes both types
    // (one per metering) and each metering both types with three or four operators. The
    // operator maps pixels and the writer takes what it mapped, so all 28 combinations ran the
    // same code as these 14.
    const char* const ops[] = {"reinhard", "drago", "hable", "agx", "aces", "exposure", "none"};
    const char* const meterings[] = {"log-average", "histogram"};
    for (int o = 0; o < 7; ++o)
        for (int m = 0; m < 2; ++m) {
            const char* const op = ops[o];
            const char* const metering = meterings[m];
            const char* const ext = (o + m) % 2 ? "exr" : "png";
            const std::string options =
                std::string(" --op ") + op + " --metering " + metering + " --exposure 0.5 ";
            const std::string whole = std::string("whole.") + ext;
            const std::string streamed = std::string("streamed.") + ext;
            ASSERT_EQ(run("dhdr-tonemap " + path("h.exr") + options + "-o " + path(whole)).status,
                      0);
            const Result r = run("dhdr-tonemap -v " + path("h.exr") + options + "--memory 0 -o " +
                                 path(streamed));
            ASSERT_EQ(r.status, 0) << r.err;
            EXPECT_TRUE(samePixels(whole, streamed)) << options << ext;
        }
    // 16 bits, and reinhard-local, which reads the frame whole whatever --memory says.
    for (const char* options : {" --bits 16 ", " --op reinhard-local "}) {
        ASSERT_EQ(run("dhdr-tonemap " + path("h.exr") + options + "-o " + path("w.png")).status, 0);
        ASSERT_EQ(run("dhdr-tonemap " + path("h.exr") + options + "--memory 0 -o " + path("s.png"))
                      .status,
                  0);
        EXPECT_TRUE(samePixels("w.png", "s.png")) << options;
    }
}

TEST_F(Tools, AdaptationSplitIntoProcessesIsOneAdaptRun) {
    // Six frames of the lit Cornell box, eight times brighter from frame 4 on.
    fs::create_directories(dir / "split");
    const ImageBuf lit = read("h.exr");
    for (int f = 1; f <= 6; ++f) {
        ImageBuf frame = OIIO::ImageBufAlgo::mul(lit, f < 4 ? 1.0f : 8.0f);
        char name[64];
        std::snprintf(name, sizeof name, "split/in.%04d.exr", f);
        ASSERT_TRUE(frame.write(path(name)));
    }
    const std::string in = " " + path("split/in.####.exr") + " ";
    Result r = run("dhdr-tonemap" + in + "--adapt --fps 30 --stats-out " +
                   path("split/whole.json") + " -o " + path("split/whole.####.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    // Metering in two chunks, the scan given them out of order, mapping in two chunks (one
    // streamed).
    r = run("dhdr-tonemap" + in + "--frames 1-2 --meter-only --stats-out " + path("split/m1.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("dhdr-tonemap" + in + "--frames 3-6 --meter-only --stats-out " + path("split/m2.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("dhdr-tonemap --scan " + path("split/m2.json") + " " + path("split/m1.json") +
            " --fps 30 --stats-out " + path("split/adapted.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("dhdr-tonemap" + in + "--frames 1-3 --adapt-from " + path("split/adapted.json") +
            " -o " + path("split/part.####.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("dhdr-tonemap" + in + "--frames 4-6 --memory 0 --adapt-from " +
            path("split/adapted.json") + " -o " + path("split/part.####.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    for (int f = 1; f <= 6; ++f) {
        char whole[64], part[64];
        std::snprintf(whole, sizeof whole, "split/whole.%04d.png", f);
        std::snprintf(part, sizeof part, "split/part.%04d.png", f);
        EXPECT_TRUE(samePixels(whole, part)) << f;
    }
    // The adaptation mattered: frame 4 mapped on its own metering differs.
    ASSERT_EQ(
        run("dhdr-tonemap " + path("split/in.0004.exr") + " -o " + path("split/own.png")).status,
        0);
    EXPECT_FALSE(samePixels("split/own.png", "split/whole.0004.png"));
    // The scanned file holds the whole run's numbers, digit for digit.
    const std::string whole = slurp(dir / "split/whole.json");
    const std::string scanned = slurp(dir / "split/adapted.json");
    EXPECT_EQ(whole.substr(whole.find("\"frames\"")), scanned.substr(scanned.find("\"frames\"")));

    // Errors: a frame the file lacks, another metering, a frame in two chunks, wrong modes.
    r = run("dhdr-tonemap" + in + "--frames 1-7 --adapt-from " + path("split/adapted.json") +
            " -o " + path("split/bad.####.png"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("has no frame 7"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("split/bad.0001.png")));
    r = run("dhdr-tonemap" + in + "--weights rec709 --adapt-from " + path("split/adapted.json") +
            " -o " + path("split/bad.####.png"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("metered with"), std::string::npos) << r.err;
    r = run("dhdr-tonemap --scan " + path("split/m1.json") + " " + path("split/m1.json") +
            " --stats-out " + path("split/twice.json"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("frame 1 is in both"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("split/twice.json")));
    r = run("dhdr-tonemap" + in + "--adapt-from " + path("split/m1.json") + " -o " +
            path("split/bad.####.png"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("holds no adapted luminance"), std::string::npos) << r.err;
    EXPECT_EQ(run("dhdr-tonemap" + in + "--meter-only -o " + path("split/x.####.png")).status, 2);
    EXPECT_EQ(run("dhdr-tonemap --scan " + path("split/m1.json")).status, 2);
    EXPECT_EQ(run("dhdr-tonemap" + in + "--adapt --adapt-from " + path("split/adapted.json") +
                  " -o " + path("split/x.####.png"))
                  .status,
              2);
}

TEST_F(Tools, EveryToolTakesFramePatterns) {
    // Two G-buffer frames of the same scene, lit, anti-aliased and bloomed as sequences.
    Result r = run("dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --size 32x24 --frames 1-2 -o " +
                   path("f.####.gbuf.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("dhdr-light " + path("f.####.gbuf.exr") + " --lights " + kTestdata +
            "/cornell_box.lights.json -o " + path("f.%04d.hdr.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("dhdr-aa " + path("f.####.hdr.exr") + " --gbuffer " + path("f.####.gbuf.exr") + " -o " +
            path("f.####.aa.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    r = run("dhdr-bloom " + path("f.####.aa.exr") + " --frames 2-2 -o " + path("f.####.bloom.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* name :
         {"f.0001.gbuf.exr", "f.0002.gbuf.exr", "f.0001.hdr.exr", "f.0002.hdr.exr", "f.0001.aa.exr",
          "f.0002.aa.exr", "f.0002.bloom.exr"})
        EXPECT_TRUE(fs::exists(path(name))) << name;
    EXPECT_FALSE(fs::exists(path("f.0001.bloom.exr")));
    // A pattern on one side only is a usage error.
    r = run("dhdr-bloom " + path("f.####.aa.exr") + " -o " + path("single.exr"));
    EXPECT_EQ(r.status, 2);
}

TEST_F(Tools, PipelineEndToEnd) {
    ASSERT_EQ(
        run("dhdr-aa " + path("h.exr") + " --gbuffer " + path("g.exr") + " -o " + path("aa.exr"))
            .status,
        0);
    ASSERT_EQ(run("dhdr-bloom " + path("aa.exr") + " -o " + path("bloom.exr")).status, 0);
    const Result r = run("dhdr-tonemap -v " + path("bloom.exr") + " -o " + path("final.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("log-average luminance "), std::string::npos) << r.err;
    const ImageBuf png = read("final.png");
    ASSERT_TRUE(png.initialized());
    EXPECT_EQ(png.spec().width, 96);
    EXPECT_EQ(png.spec().height, 72);
    EXPECT_EQ(png.nativespec().format, OIIO::TypeDesc::UINT8);
    // The lit HDR keeps the G-buffer's camera.
    const ImageBuf hdr = read("h.exr");
    EXPECT_NE(hdr.spec().find_attribute("worldToCamera"), nullptr);
    EXPECT_GE(hdr.spec().channelindex("N.X"), 0); // --aovs
    // 16-bit PNG by option.
    ASSERT_EQ(run("dhdr-tonemap " + path("h.exr") + " --bits 16 -o " + path("deep.png")).status, 0);
    EXPECT_EQ(read("deep.png").nativespec().format, OIIO::TypeDesc::UINT16);
}

TEST_F(Tools, OpNoneIsTheConfigsViewAlone) {
    // A v2 config whose view tone-maps (a compressing matrix and a 2.2 power before a 2.4
    // display encoding): --op none hands the scene-linear pixels to it unclipped, and the PNG
    // equals oiiotool --ociodisplay's within 1 LSB, highlights above 1 included.
    const std::string cfg = path("film.ocio");
    std::ofstream(cfg) << R"(ocio_profile_version: 2
roles:
  scene_linear: linear
  default: linear
file_rules:
  - !<Rule> {name: Default, colorspace: default}
displays:
  Screen:
    - !<View> {name: Film, view_transform: film, display_colorspace: gamma24}
view_transforms:
  - !<ViewTransform>
    name: film
    from_scene_reference: !<GroupTransform>
      children:
        - !<MatrixTransform> {matrix: [0.2, 0, 0, 0, 0, 0.2, 0, 0, 0, 0, 0.2, 0, 0, 0, 0, 1]}
        - !<ExponentTransform> {value: [2.2, 2.2, 2.2, 1], direction: inverse}
display_colorspaces:
  - !<ColorSpace>
    name: gamma24
    from_display_reference: !<ExponentTransform> {value: [2.4, 2.4, 2.4, 1], direction: inverse}
colorspaces:
  - !<ColorSpace>
    name: linear
)";
    // A ramp from 0 to 4.5 in scene-linear, some of it far above 1.
    OIIO::ImageSpec spec(256, 8, 3, OIIO::TypeDesc::FLOAT);
    ImageBuf ramp(spec);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 256; ++x) {
            const float v = 4.5f * float(x) / 255.0f;
            const float c[3] = {v, 0.5f * v, 0.25f * v * float(y) / 7.0f};
            ramp.setpixel(x, y, c);
        }
    ASSERT_TRUE(ramp.write(path("ramp.exr")));
    const Result r =
        run("dhdr-tonemap " + path("ramp.exr") + " --ocio-config " + cfg +
            " --display Screen --view Film --op none --no-dither -o " + path("none.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string oiio = "oiiotool " + path("ramp.exr") + " --colorconfig " + cfg +
                             " --ociodisplay:from=linear Screen Film -d uint8 -o " +
                             path("oiio.png") + " >/dev/null 2>&1";
    ASSERT_EQ(std::system(oiio.c_str()), 0);
    const ImageBuf a = read("none.png"), b = read("oiio.png");
    ASSERT_EQ(a.spec().width, 256);
    float worst = 0.0f;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 256; ++x)
            for (int c = 0; c < 3; ++c)
                worst =
                    std::max(worst, std::abs(a.getchannel(x, y, 0, c) - b.getchannel(x, y, 0, c)));
    EXPECT_LE(worst, 1.0f / 255.0f + 1e-6f);
    // The ramp's top reaches the view's shoulder above 1 (not clipped before the view).
    EXPECT_LT(a.getchannel(200, 0, 0, 0), a.getchannel(255, 0, 0, 0));
    // --op exposure, which clips at 1 first, does differ there.
    ASSERT_EQ(run("dhdr-tonemap " + path("ramp.exr") + " --ocio-config " + cfg +
                  " --display Screen --view Film --op exposure --no-dither -o " + path("clip.png"))
                  .status,
              0);
    EXPECT_GT(std::abs(read("clip.png").getchannel(255, 0, 0, 0) - b.getchannel(255, 0, 0, 0)),
              0.1f);
}

TEST_F(Tools, OpNoneWithTheBuiltinStandardViewIsThePlainSrgbEncoding) {
    OIIO::ImageSpec spec(64, 1, 3, OIIO::TypeDesc::FLOAT);
    ImageBuf ramp(spec);
    for (int x = 0; x < 64; ++x) {
        const float v = float(x) / 63.0f;
        const float c[3] = {v, v * v, 0.5f};
        ramp.setpixel(x, 0, c);
    }
    ASSERT_TRUE(ramp.write(path("ramp2.exr")));
    ASSERT_EQ(
        run("dhdr-tonemap " + path("ramp2.exr") + " --op none --no-dither -o " + path("srgb.png"))
            .status,
        0);
    const ImageBuf a = read("srgb.png");
    auto encode = [](double v) {
        return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    };
    for (int x = 0; x < 64; ++x)
        for (int c = 0; c < 3; ++c) {
            float in[3];
            ramp.getpixel(x, 0, in);
            EXPECT_NEAR(a.getchannel(x, 0, 0, c), std::round(encode(in[c]) * 255.0) / 255.0,
                        1.0 / 255.0 + 1e-6)
                << x << " " << c;
        }
}
