// Input that should be an error and was a crash, an abort, a leftover file or silent
// nonsense (issue 8, items 11–17 and the smaller ones): a clear message, a non-zero exit
// status, no output and no temporary left behind.
#include "animation_writer.h"
#include "tool_test.h"

#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <chrono>
#include <csignal>
#include <sys/types.h>
#include <thread>
#include <unistd.h>

using namespace dhdr::test;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

const std::string kCornell = kTestdata + "/cornell_box.gltf";
const std::string kLights = kTestdata + "/cornell_box.lights.json";

class BadInput : public ToolTest {
protected:
    static void SetUpTestSuite() {
        makeScratch();
        sharedInputs([] {
            ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 32x24 -o " + path("g.exr")).status,
                      0);
            ASSERT_EQ(
                run("dhdr-light " + path("g.exr") + " --lights " + kLights + " -o " + path("h.exr"))
                    .status,
                0);
        });
    }

    // `r` failed with status `status`, saying `what`, and left neither `out` nor temporaries.
    static void expectFailure(const Result& r, int status, const std::string& what,
                              const std::string& out = {}) {
        EXPECT_EQ(r.status, status) << r.err;
        EXPECT_NE(r.err.find(what), std::string::npos) << "expected '" << what << "' in: " << r.err;
        if (!out.empty()) {
            EXPECT_FALSE(fs::exists(out)) << out;
        }
        EXPECT_TRUE(noTemporaries());
    }

    // Starts `args` in the background; returns its process id.
    static pid_t start(const std::string& args) {
        const pid_t pid = fork();
        if (pid == 0) {
            const std::string cmd = "exec " + kTools + "/" + args + " 2>/dev/null";
            execl("/bin/sh", "sh", "-c", cmd.c_str(), nullptr);
            _exit(127);
        }
        return pid;
    }

    static int temporaries() {
        int n = 0;
        for (const auto& e : fs::directory_iterator(dir))
            n += e.path().filename().string().find(".tmp") != std::string::npos;
        return n;
    }

    // Waits up to 60 s, while process `pid` runs, for at least `count` temporaries to exist.
    static bool waitForTemporaries(int count, pid_t pid) {
        for (int i = 0; i < 6000; ++i) {
            if (temporaries() >= count) return true;
            int status = 0;
            if (waitpid(pid, &status, WNOHANG) == pid) return false; // it finished first
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return false;
    }
};

} // namespace

// 11, 15. A header that claims 65536 × 65536 pixels whose rows are absent: a stage that holds
// whole frames (dhdr-tonemap --op reinhard-local) refuses it before the allocation, naming the
// file and the size; the stages that stream strips (dhdr-light, dhdr-aa, dhdr-bloom and
// dhdr-tonemap's other operators) never need the whole frame and fail at the first absent
// row. None leaves an output. (--max-pixels 0 lifts the pixel limit, which would refuse the
// header first: HostileInput.PixelLimitIsCheckedByEveryTool.)
TEST_F(BadInput, HugeHeaderIsRefusedBeforeAllocating) {
    claimHugeSize(path("h.exr"), path("huge.exr"), 65536);
    claimHugeSize(path("g.exr"), path("huge_g.exr"), 65536);
    const std::string local = "dhdr-tonemap --max-pixels 0 --op reinhard-local " +
                              path("huge.exr") + " -o " + path("huge_out.exr");
    expectFailure(run(local), 1, "huge.exr: cannot read: its 65536x65536 pixels",
                  path("huge_out.exr"));
    for (const std::string& tool : {std::string("dhdr-bloom"), std::string("dhdr-tonemap"),
                                    "dhdr-aa --gbuffer " + path("huge_g.exr")})
        expectFailure(
            run(tool + " --max-pixels 0 " + path("huge.exr") + " -o " + path("huge_out.exr")), 1,
            "huge.exr: cannot read", path("huge_out.exr"));
    expectFailure(run("dhdr-light --max-pixels 0 " + path("huge_g.exr") + " --lights " + kLights +
                      " -o " + path("huge_out.exr")),
                  1, "huge_g.exr: cannot read", path("huge_out.exr"));
    const Result r = run(local);
    EXPECT_NE(r.err.find("GB as float, more than this machine's"), std::string::npos) << r.err;
}

// 12. SIGHUP while a frame is written, SIGINT while several frames are: nothing left.
TEST_F(BadInput, SignalsLeaveNoTemporaries) {
    const pid_t one =
        start("dhdr-gbuffer " + kCornell + " --size 6000x6000 --threads 1 -o " + path("big.exr"));
    ASSERT_TRUE(waitForTemporaries(1, one));
    kill(one, SIGHUP);
    int status = 0;
    waitpid(one, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGHUP);
    EXPECT_EQ(temporaries(), 0);
    EXPECT_FALSE(fs::exists(path("big.exr")));

    // Frames mapped two at a time: two temporaries open at once. Eight frames, so that on a
    // loaded machine (CI runs tests side by side) two of them still overlap (with four, one
    // run in many saw none while the polling looked).
    const ImageBuf frame = ImageBuf(ImageSpec(2500, 2500, 3, TypeDesc::HALF));
    for (int f = 1; f <= 8; ++f)
        ASSERT_TRUE(frame.write(path("seq." + std::to_string(f) + ".exr")));
    const pid_t many =
        start("dhdr-tonemap " + path("seq.#.exr") + " --threads 2 -o " + path("seq.#.png"));
    ASSERT_TRUE(waitForTemporaries(2, many)) << "dhdr-tonemap ended before two frames overlapped";
    kill(many, SIGINT);
    waitpid(many, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT);
    EXPECT_EQ(temporaries(), 0);
}

// 12. A temporary whose writer was killed (SIGKILL: no handler runs) is removed by the next
// run that writes the same output; one of a live process is not.
TEST_F(BadInput, StaleTemporariesAreRemoved) {
    const pid_t gone = fork();
    if (gone == 0) _exit(0);
    waitpid(gone, nullptr, 0);
    const std::string stale = path(".bloomed.tmp" + std::to_string(gone) + ".exr");
    const std::string live = path(".bloomed.tmp" + std::to_string(getpid()) + ".exr");
    std::ofstream(stale) << "left by a killed run";
    std::ofstream(live) << "being written";
    ASSERT_EQ(run("dhdr-bloom " + path("h.exr") + " -o " + path("bloomed.exr")).status, 0);
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(live));
    fs::remove(live);
}

// 13. A deep EXR: every tool says it takes flat images.
TEST_F(BadInput, DeepInputIsRefused) {
    ImageSpec spec(8, 8, 5, TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "A", "Z"};
    spec.alpha_channel = 3;
    spec.z_channel = 4;
    spec.deep = true;
    ImageBuf deep(spec);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            deep.set_deep_samples(x, y, 0, 2);
            for (int s = 0; s < 2; ++s)
                for (int c = 0; c < 5; ++c)
                    deep.set_deep_value(x, y, 0, c, s, c == 4 ? 1.0f + float(s) : 0.5f);
        }
    ASSERT_TRUE(deep.write(path("deep.exr")));
    const std::string out = path("deep_out.exr");
    for (const std::string& c : {"dhdr-tonemap " + path("deep.exr") + " -o " + out,
                                 "dhdr-bloom " + path("deep.exr") + " -o " + out,
                                 "dhdr-aa " + path("deep.exr") + " -o " + out})
        expectFailure(run(c), 1, "deep.exr: cannot read: is a deep image", out);
    // A deep G-buffer is read for its front samples, and checked like a flat one.
    expectFailure(run("dhdr-aa " + path("h.exr") + " --gbuffer " + path("deep.exr") + " -o " + out),
                  1, "deep.exr: is 8x8", out);
    expectFailure(run("dhdr-light " + path("deep.exr") + " --lights " + kLights + " -o " + out), 1,
                  "deep.exr", out);
}

// 14, 17. Numbers out of range or not finite: usage errors, with the range in --help.
TEST_F(BadInput, NumericOptionsAreChecked) {
    const std::string h = path("h.exr"), g = path("g.exr"), out = path("opt_out.exr");
    const std::pair<std::string, std::string> cases[] = {
        {"dhdr-light " + g + " --lights " + kLights + " --tile 2147483647", "--tile"},
        {"dhdr-light " + g + " --lights " + kLights + " --tile 0", "--tile"},
        {"dhdr-light " + g + " --lights " + kLights + " --background nan,0,0", "--background"},
        {"dhdr-bloom " + h + " --sigma 20000", "--sigma"},
        {"dhdr-bloom " + h + " --sigma 1e30", "--sigma"},
        {"dhdr-bloom " + h + " --sigma inf", "--sigma"},
        {"dhdr-bloom " + h + " --strength nan", "--strength"},
        {"dhdr-tonemap " + h + " --exposure nan", "--exposure"},
        {"dhdr-tonemap " + h + " --key inf", "--key"},
        {"dhdr-tonemap " + h + " --bits 12", "--bits: 12 is not 8 or 16"},
        {"dhdr-aa " + h + " --max-offset -1", "--max-offset"},
        {"dhdr-gbuffer " + kCornell + " --threads 10000", "--threads"},
    };
    for (const auto& [command, what] : cases)
        expectFailure(run(command + " -o " + out), 2, what, out);
    expectFailure(run("dhdr-tonemap " + h + " --bits 16 -o " + path("x.jpg")), 2, "JPEG",
                  path("x.jpg"));
    expectFailure(run("dhdr-bloom " + path("seq.####.exr") + " --frames 2147483646-2147483647 -o " +
                      path("seq_out.####.exr")),
                  2, "--frames");
    expectFailure(run("dhdr-tonemap " + path("seq.####.exr") +
                      " --frames 2147483646-2147483647 -o " + path("seq_out.####.png")),
                  2, "--frames");
    const Result help = run("dhdr-bloom --help");
    EXPECT_NE(help.out.find("[0, 64]"), std::string::npos) << help.out;
}

// 16. What used to escape main as an exception or crash inside Assimp.
TEST_F(BadInput, MalformedScenesAndLightsAreErrors) {
    // A glTF light whose intensity is a string (Assimp accepts the file).
    nlohmann::json doc = gltfWithMesh(squareMesh());
    doc["extensionsUsed"] = {"KHR_lights_punctual"};
    doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"intensity", "bright"}}};
    doc["nodes"] = {{{"name", "square"}, {"mesh", 0}},
                    {{"name", "lamp"},
                     {"translation", {0, 0, 2}},
                     {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}};
    doc["scenes"] = {{{"nodes", {0, 1}}}};
    writeJson(path("string_light.gltf"), doc);
    expectFailure(run("dhdr-gbuffer " + path("string_light.gltf") + " --lookat 0,0,3,0,0,0 -o " +
                      path("sl.exr")),
                  1, "light 0: \"intensity\" must be a number", path("sl.exr"));

    // 15,000 nested nodes: no stack overflow.
    doc = gltfWithMesh(squareMesh());
    nlohmann::json nodes = nlohmann::json::array();
    for (int i = 0; i < 15000; ++i)
        nodes.push_back({{"name", "n" + std::to_string(i)}, {"children", {i + 1}}});
    nodes.push_back({{"name", "square"}, {"mesh", 0}});
    doc["nodes"] = nodes;
    doc["scenes"] = {{{"nodes", {0}}}};
    writeJson(path("deep_nodes.gltf"), doc);
    const Result nested = run("dhdr-gbuffer " + path("deep_nodes.gltf") +
                              " --lookat 0,0,3,0,0,0 --size 8x8 -o " + path("dn.exr"));
    EXPECT_TRUE(nested.status == 0 || nested.status == 1) << nested.status << nested.err;

    // A PLY face that indexes past the vertices.
    std::ofstream(path("bad.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                      "property float y\nproperty float z\nelement face 1\n"
                                      "property list uchar int vertex_indices\nend_header\n"
                                      "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
    expectFailure(
        run("dhdr-gbuffer " + path("bad.ply") + " --lookat 0,0,3,0,0,0 -o " + path("ply.exr")), 1,
        "bad.ply: cannot load the scene:", path("ply.exr"));

    // A glTF whose scene has no nodes (Khronos' SceneWithoutNodes): a reason after the colon.
    doc = gltfWithMesh(squareMesh());
    doc["scenes"] = {{{"name", "empty"}}};
    doc["scene"] = 0;
    writeJson(path("no_nodes.gltf"), doc);
    const Result empty =
        run("dhdr-gbuffer " + path("no_nodes.gltf") + " --lookat 0,0,3,0,0,0 -o " + path("nn.exr"));
    EXPECT_EQ(empty.status, 1);
    EXPECT_NE(empty.err.find("cannot load the scene: its scene has no nodes"), std::string::npos)
        << empty.err;

    // Lights files: a number no double holds, one no float holds, and a folder.
    std::ofstream(path("huge_number.json"))
        << R"({"lights": [{"type": "point", "position": [0, 1, 0], "intensity": 1e400}]})";
    std::ofstream(path("float_overflow.json"))
        << R"({"lights": [{"type": "point", "position": [0, 1, 0], "intensity": 1e39}]})";
    fs::create_directories(dir / "lights_dir");
    const std::string light = "dhdr-light " + path("g.exr") + " -o " + path("l.exr") + " --lights ";
    expectFailure(run(light + path("huge_number.json")), 1, "huge_number.json: not valid JSON",
                  path("l.exr"));
    expectFailure(run(light + path("float_overflow.json")), 1,
                  "light 0: \"intensity\" must be a number", path("l.exr"));
    expectFailure(run(light + path("lights_dir")), 1, "lights_dir: is a folder", path("l.exr"));
}

// 17. G-buffers with unusable camera matrices or channels of the wrong type.
TEST_F(BadInput, BrokenGBuffersAreRefused) {
    ImageBuf g(path("g.exr"));
    ASSERT_TRUE(g.read(0, 0, true, TypeDesc::FLOAT));
    const float zero[16] = {};
    g.specmod().attribute("worldToNDC", OIIO::TypeMatrix44, zero);
    ASSERT_TRUE(g.write(path("zero_ndc.exr")));
    expectFailure(
        run("dhdr-light " + path("zero_ndc.exr") + " --lights " + kLights + " -o " + path("z.exr")),
        1, "zero_ndc.exr: the header's worldToNDC is not a usable camera matrix", path("z.exr"));

    ImageBuf uintNormals(path("g.exr"));
    ASSERT_TRUE(uintNormals.read(0, 0, true, TypeDesc::FLOAT));
    std::vector<TypeDesc> formats(size_t(uintNormals.nchannels()), TypeDesc::FLOAT);
    for (int c = 0; c < uintNormals.nchannels(); ++c)
        if (uintNormals.spec().channelnames[size_t(c)].rfind("N.", 0) == 0)
            formats[size_t(c)] = TypeDesc::UINT;
    uintNormals.set_write_format(formats);
    ASSERT_TRUE(uintNormals.write(path("uint_normals.exr")));
    expectFailure(run("dhdr-light " + path("uint_normals.exr") + " --lights " + kLights + " -o " +
                      path("u.exr")),
                  1, "uint_normals.exr: channel 'N.X' is stored as uint", path("u.exr"));
}

// Normals that are no direction (issue 48: NaN or −Inf in every component, read as 0, or zero
// indexed the multiple-scattering table with a NaN cosine, SIGSEGV): lit with the geometric
// normal Ng, else facing the camera, with a warning that counts them; every output value finite.
// +Inf is read as 65504 (the one rule for non-finite values): a direction, shaded as it is.
TEST_F(BadInput, NormalsWithoutADirectionAreRepaired) {
    ImageBuf clean(path("g.exr"));
    ASSERT_TRUE(clean.read(0, 0, true, TypeDesc::FLOAT));
    const int n = clean.spec().channelindex("N.X");
    const float poison[4] = {NAN, -INFINITY, 0.0f, INFINITY};
    // Four covered pixels of the middle row (the Cornell box fills the frame).
    ImageBuf bad;
    bad.copy(clean);
    for (int i = 0; i < 4; ++i) {
        float* p = static_cast<float*>(bad.pixeladdr(10 + 4 * i, 12));
        ASSERT_GT(p[0], 0.0f) << "pixel " << 10 + 4 * i << " is not covered";
        p[n] = p[n + 1] = p[n + 2] = poison[i];
    }
    ASSERT_TRUE(bad.write(path("bad_normals.exr")));
    const std::string light = " --lights " + kLights + " --type float -o ";
    ASSERT_EQ(run("dhdr-light " + path("g.exr") + light + path("clean_lit.exr")).status, 0);
    const Result r = run("dhdr-light " + path("bad_normals.exr") + light + path("bad_lit.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("bad_normals.exr: replaced 9 non-finite values (3 NaN → 0, 3 +Inf"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("bad_normals.exr: 3 surface samples with a normal of zero length"),
              std::string::npos)
        << r.err;
    const ImageBuf lit = read("bad_lit.exr"), reference = read("clean_lit.exr");
    EXPECT_TRUE(allFinite(lit));
    // The box's walls are flat: N is Ng there but for N's rounding to half.
    for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 4; ++c) {
            const float want = reference.getchannel(10 + 4 * i, 12, 0, c);
            EXPECT_NEAR(lit.getchannel(10 + 4 * i, 12, 0, c), want, 1e-2f * want + 1e-4f)
                << "pixel " << 10 + 4 * i << ", channel " << c;
        }
    // Without Ng the surface faces the camera: lit, finite.
    std::vector<int> keep;
    for (int c = 0; c < bad.nchannels(); ++c)
        if (bad.spec().channelnames[size_t(c)].rfind("Ng.", 0) != 0) keep.push_back(c);
    const ImageBuf noNg = OIIO::ImageBufAlgo::channels(bad, int(keep.size()), keep);
    ASSERT_TRUE(noNg.write(path("bad_normals_no_ng.exr")));
    const Result without =
        run("dhdr-light " + path("bad_normals_no_ng.exr") + light + path("no_ng_lit.exr"));
    ASSERT_EQ(without.status, 0) << without.err;
    EXPECT_NE(without.err.find("3 surface samples with a normal of zero length"), std::string::npos)
        << without.err;
    const ImageBuf facing = read("no_ng_lit.exr");
    EXPECT_TRUE(allFinite(facing));
    for (int i = 0; i < 4; ++i)
        EXPECT_GT(facing.getchannel(10 + 4 * i, 12, 0, 0), 0.0f) << "pixel " << 10 + 4 * i;
}

// Accessor and bufferView offsets that are negative or wrap round (issue 48: a byteOffset of
// 2^64 − 2^40 with a 2^40 stride pointed 1 TiB before the buffer, SIGSEGV): exit 1 naming the
// file, the animation, the accessor and the offset, no output; --info says why it is unusable.
TEST_F(BadInput, AccessorOffsetsThatWrapOrAreNegativeAreErrors) {
    struct Damage {
        const char* name;
        void (*apply)(nlohmann::json& view, nlohmann::json& accessor);
        const char* problem;
    };
    const Damage damages[] = {
        {"stride_wrap",
         [](nlohmann::json& v, nlohmann::json& a) {
             v["byteStride"] = std::uint64_t(1) << 40;
             a["byteOffset"] = std::uint64_t(0) - (std::uint64_t(1) << 40);
         },
         "its byteOffset 18446742974197923840 is past the end of bufferView"},
        {"offset_wrap",
         [](nlohmann::json&, nlohmann::json& a) { a["byteOffset"] = std::uint64_t(0) - 8; },
         "its byteOffset 18446744073709551608 is past the end of bufferView"},
        {"stride_past",
         [](nlohmann::json& v, nlohmann::json&) { v["byteStride"] = std::uint64_t(1) << 40; },
         "its 2 elements run past bufferView"},
        {"offset_negative", [](nlohmann::json&, nlohmann::json& a) { a["byteOffset"] = -16; },
         "its byteOffset -16 is not a whole number"},
        {"view_negative", [](nlohmann::json& v, nlohmann::json&) { v["byteOffset"] = -16; },
         "'s byteOffset -16 is not a whole number"},
        {"view_wrap",
         [](nlohmann::json& v, nlohmann::json&) { v["byteOffset"] = std::uint64_t(0) - 8; },
         "(byteOffset 18446744073709551608, byteLength 24) runs past buffer"},
    };
    for (const Damage& d : damages) {
        SCOPED_TRACE(d.name);
        nlohmann::json doc = squareAndCamera();
        addChannel(doc, 0, 0, "translation", {0.0f, 2.0f}, {-1, 0, 0, 1, 0, 0});
        const size_t output = doc["animations"][0]["samplers"][0]["output"];
        nlohmann::json& accessor = doc["accessors"][output];
        d.apply(doc["bufferViews"][accessor["bufferView"].get<size_t>()], accessor);
        const std::string file = std::string(d.name) + ".gltf";
        writeJson(path(file), doc);
        const std::string out = std::string(d.name) + ".exr";
        const Result r = run("dhdr-gbuffer " + path(file) + " --size 16x16 -o " + path(out));
        expectFailure(r, 1,
                      file + ": animation 'anim0' cannot be played: sampler 0: output accessor " +
                          std::to_string(output) + ": ",
                      path(out));
        EXPECT_NE(r.err.find(d.problem), std::string::npos) << r.err;
        const Result info = run("dhdr-gbuffer " + path(file) + " --info");
        EXPECT_EQ(info.status, 0) << info.err;
        EXPECT_NE(info.out.find("unusable: sampler 0: output accessor"), std::string::npos)
            << info.out;
    }
}

// Smaller: the help lists every light type.
TEST_F(BadInput, LightHelpListsEveryLightType) {
    const Result r = run("dhdr-light --help");
    for (const char* type : {"point", "spot", "directional", "ambient", "sphere", "rectangle"})
        EXPECT_NE(r.out.find(type), std::string::npos) << type;
}

// Smaller: a PNG holds sRGB-encoded values; mapped with the identity operator (exposure 0)
// it comes back as it was, not brightened by a second encoding.
TEST_F(BadInput, PngInputIsDecodedFromSrgb) {
    ImageBuf ramp(ImageSpec(256, 4, 3, TypeDesc::FLOAT));
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 256; ++x)
            for (int c = 0; c < 3; ++c)
                static_cast<float*>(ramp.pixeladdr(x, y))[c] = float(x) / 255.0f;
    ASSERT_TRUE(ramp.write(path("ramp.png"), TypeDesc::UINT8));
    const Result r = run("dhdr-tonemap " + path("ramp.png") + " --op exposure --no-dither -v -o " +
                         path("ramp_out.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("decoded from 'sRGB - Texture'"), std::string::npos) << r.err;
    const ImageBuf out = read("ramp_out.png");
    float worst = 0.0f;
    for (int x = 0; x < 256; ++x)
        worst = std::max(worst, std::abs(out.getchannel(x, 1, 0, 1) * 255.0f - float(x)));
    EXPECT_LE(worst, 1.0f);
}

// Smaller: a sequence with a hole in it says which frames are missing.
TEST_F(BadInput, MissingFramesOfASequenceAreNamed) {
    const ImageBuf frame = read("h.exr");
    for (int f : {1, 2, 4})
        ASSERT_TRUE(frame.write(path("gap." + std::to_string(f) + ".exr")));
    const Result r = run("dhdr-tonemap " + path("gap.#.exr") + " --adapt -o " + path("gap.#.png"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("1 frames missing from the sequence (" + path("gap.3.exr") + ")"),
              std::string::npos)
        << r.err;
}
