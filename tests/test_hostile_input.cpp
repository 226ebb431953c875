// Hostile input from issue 21, run as a user runs the tools: each case ends in a clear
// message naming the file and what is wrong, exit 1 (bad input) or 2 (usage), and no output
// or temporary left behind.
#include "tool_test.h"

#include <chrono>
#include <csignal>
#include <sys/types.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace dhdr::test;

namespace {

const std::string kCornell = kTestdata + "/cornell_box.gltf";
const std::string kLights = kTestdata + "/cornell_box.lights.json";

class HostileInput : public ToolTest {
protected:
    static void SetUpTestSuite() {
        makeScratch();
        sharedInputs([] {
            ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 32x24 -o " + path("g.exr")).status,
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

    // run() from the scratch folder, so that files are named there as a user names them
    // (a name that begins with '-' included).
    static Result runHere(const std::string& args) {
        Result r;
        const std::string cmd = "cd '" + dir.string() + "' && env -u OCIO " + kTools + "/" + args +
                                " >stdout.txt 2>stderr.txt </dev/null";
        const int raw = std::system(cmd.c_str());
        r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
        r.out = slurp(dir / "stdout.txt");
        r.err = slurp(dir / "stderr.txt");
        return r;
    }
};

} // namespace

// A misspelt key in a lights file ("colour", "rnage") was dropped and the light rendered at
// its defaults with exit 0; now dhdr-light and dhdr-probes refuse the file, naming the key
// and the light.
TEST_F(HostileInput, MisspeltLightKeysAreErrors) {
    std::ofstream(path("colour.json")) << R"({"lights": [
        {"type": "ambient", "intensity": 0.1},
        {"type": "point", "name": "bulb", "position": [0.28, 0.45, 0.28], "colour": [1, 0, 0]}]})";
    std::ofstream(path("rnage.json"))
        << R"([{"type": "spot", "position": [0.1, 0.45, 0.05], "direction": [0, -1, 0],
               "rnage": 1.6}])";
    const std::string light = "dhdr-light " + path("g.exr") + " -o " + path("l.exr") + " --lights ";
    expectFailure(run(light + path("colour.json")), 1,
                  "colour.json: light 1 (point \"bulb\"): unknown key \"colour\" (did you mean "
                  "\"color\"?)",
                  path("l.exr"));
    expectFailure(run(light + path("rnage.json")), 1,
                  "rnage.json: light 0 (spot): unknown key \"rnage\" (did you mean \"range\"?)",
                  path("l.exr"));
    expectFailure(run("dhdr-probes " + kCornell + " --lights " + path("colour.json") + " -o " +
                      path("p.exr")),
                  1, "colour.json: light 1 (point \"bulb\"): unknown key \"colour\"",
                  path("p.exr"));
    // The project's own lights files, and what dhdr-gbuffer --lights-out writes, still load.
    for (const std::string& file : {kLights, kTestdata + "/cornell_box.fill.lights.json"})
        EXPECT_EQ(run(light + file).status, 0) << file;
    ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 8x8 --lights-out " +
                  path("out.lights.json") + " -o " + path("g8.exr"))
                  .status,
              0);
    EXPECT_EQ(run("dhdr-light " + path("g8.exr") + " --lights " + path("out.lights.json") + " -o " +
                  path("l8.exr"))
                  .status,
              0);
}

// `nohup dhdr-… &` died on SIGHUP: the tools installed their clean-up handler over the
// SIG_IGN that nohup had set (and over the SIGINT a non-interactive shell ignores for a
// background job). The tool runs under the real nohup with SIGINT ignored too, is sent
// SIGHUP and SIGINT while its temporary output is open (the handlers are installed by
// then), and finishes its picture.
TEST_F(HostileInput, IgnoredSignalsStayIgnored) {
    const std::string out = path("nohup.exr");
    const pid_t pid = fork();
    if (pid == 0) {
        std::signal(SIGINT, SIG_IGN);
        const std::string cmd = "exec nohup " + kTools + "/dhdr-gbuffer " + kCornell +
                                " --size 1000x1000 --threads 1 -o " + out + " >" +
                                path("nohup.out") + " 2>" + path("nohup.err") + " </dev/null";
        execl("/bin/sh", "sh", "-c", cmd.c_str(), nullptr);
        _exit(127);
    }
    ASSERT_GT(pid, 0);
    auto temporaryOpen = [] {
        for (const auto& e : fs::directory_iterator(dir))
            if (e.path().filename().string().rfind(".nohup.tmp", 0) == 0) return true;
        return false;
    };
    int status = 0, signalled = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (waitpid(pid, &status, WNOHANG) == 0) {
        if (temporaryOpen()) {
            kill(pid, SIGHUP);
            kill(pid, SIGINT);
            ++signalled;
        }
        if (std::chrono::steady_clock::now() > deadline) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            FAIL() << "dhdr-gbuffer did not finish";
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_GT(signalled, 0) << "the run ended before its output was open; make it longer";
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 0) << slurp(dir / "nohup.err");
    EXPECT_TRUE(fs::exists(out));
    EXPECT_TRUE(noTemporaries());
}

// An output could overwrite an input with exit 0: -o naming the --probes or --plate file,
// --deep-out naming the G-buffer, dhdr-ibl -o naming its environment, --deep-out = -o
// sharing one temporary. Every file a tool reads, by any option, is an input; each case is a
// usage error (2) naming the file and both options, before anything is read or written, and
// the input is left as it was.
TEST_F(HostileInput, NoOutputOverwritesAnInput) {
    ASSERT_EQ(
        run("dhdr-light " + path("g.exr") + " --lights " + kLights + " -o " + path("h.exr")).status,
        0);
    fs::copy_file(kLights, path("l.json"));
    fs::copy_file(kCornell, path("scene.gltf"));
    fs::copy_file(path("h.exr"), path("plate.exr"));
    fs::copy_file(path("h.exr"), path("probes.exr"));
    fs::copy_file(path("h.exr"), path("env.exr"));
    fs::create_hard_link(path("env.exr"), path("env_link.exr"));
    fs::create_directories(dir / "sub");
    std::ofstream(path("stats.json")) << "{}";
    const std::string g = path("g.exr"), h = path("h.exr"), l = path("l.json");
    const std::string light = "dhdr-light " + g + " --lights " + l;
    struct Case {
        std::string command, message;
    };
    const Case cases[] = {
        {light + " --probes " + path("probes.exr") + " -o " + path("probes.exr"),
         "probes.exr: the output (-o) is also an input (--probes)"},
        {light + " --plate " + path("plate.exr") + " -o " + path("plate.exr"),
         "plate.exr: the output (-o) is also an input (--plate)"},
        {light + " -o " + l, "l.json: the output (-o) is also an input (--lights)"},
        {light + " --scene " + path("scene.gltf") + " -o " + path("scene.gltf"),
         "scene.gltf: the output (-o) is also an input (--scene)"},
        {light + " -o " + path("out.exr") + " --deep-out " + g,
         "g.exr: the output (--deep-out) is also an input;"},
        // Another spelling of the same file.
        {light + " -o " + path("sub/../out.exr") + " --deep-out " + dir.string() +
             "/./sub/../g.exr",
         "the output (--deep-out) is also an input;"},
        // Two outputs in one file, neither existing yet, spelt differently.
        {light + " -o " + path("d.exr") + " --deep-out " + path("sub/../d.exr"),
         "-o and --deep-out name the same file"},
        // Frame patterns: the deep output's pattern is the G-buffers'; one frame of -o is
        // the --probes file.
        {"dhdr-light " + path("g.####.exr") + " --lights " + l + " --frames 1-2 -o " +
             path("h.####.exr") + " --deep-out " + path("g.####.exr"),
         "g.####.exr: the output (--deep-out) is also an input"},
        {"dhdr-light " + path("g.####.exr") + " --lights " + l + " --frames 1-2 -o " +
             path("h.####.exr") + " --probes " + path("h.0002.exr"),
         "h.0002.exr: the output (-o) is also an input (--probes)"},
        {"dhdr-aa " + h + " --gbuffer " + g + " -o " + g,
         "g.exr: the output (-o) is also an input (--gbuffer)"},
        {"dhdr-ibl " + path("env.exr") + " -o " + path("env.exr"),
         "env.exr: the output (-o) is also an input"},
        // A hard link to the environment is the same file.
        {"dhdr-ibl " + path("env.exr") + " -o " + path("env_link.exr"),
         "env_link.exr: the output (-o) is also an input"},
        {"dhdr-probes " + path("scene.gltf") + " -o " + path("scene.gltf"),
         "scene.gltf: the output (-o) is also an input"},
        {"dhdr-probes " + path("scene.gltf") + " --lights " + l + " -o " + l,
         "l.json: the output (-o) is also an input (--lights)"},
        {"dhdr-gbuffer " + path("scene.gltf") + " --size 8x8 -o " + path("g8.exr") +
             " --lights-out " + path("scene.gltf"),
         "scene.gltf: the output (--lights-out) is also an input"},
        {"dhdr-gbuffer " + path("scene.gltf") + " --size 8x8 -o " + path("g8.exr") +
             " --lights-out " + path("g8.exr"),
         "-o and --lights-out name the same file"},
        {"dhdr-tonemap " + path("g.####.exr") + " -o " + path("t.####.png") +
             " --adapt --stats-out " + path("g.0002.exr"),
         "g.0002.exr: the output (--stats-out) is also an input"},
        {"dhdr-tonemap " + path("g.####.exr") + " --meter-only --stats-out " + path("g.0001.exr"),
         "g.0001.exr: the output (--stats-out) is also an input"},
        {"dhdr-tonemap " + path("g.####.exr") + " -o " + path("t.####.png") + " --adapt-from " +
             path("stats.json") + " --stats-out " + path("stats.json"),
         "stats.json: the output (--stats-out) is also an input (--adapt-from)"},
        {"dhdr-tonemap " + path("g.####.exr") + " -o " + path("g.####.exr"),
         "g.####.exr: the output (-o) is also an input"},
    };
    fs::copy_file(g, path("g.0001.exr"));
    fs::copy_file(g, path("g.0002.exr"));
    std::vector<std::pair<std::string, std::string>> before;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_regular_file() && e.path().filename().string().rfind("std", 0) != 0)
            before.emplace_back(e.path().string(), slurp(e.path()));
    for (const Case& c : cases) {
        SCOPED_TRACE(c.command);
        const Result r = run(c.command);
        EXPECT_EQ(r.status, 2) << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos)
            << "expected '" << c.message << "' in: " << r.err;
        EXPECT_TRUE(noTemporaries());
        for (const char* name : {"out.exr", "d.exr", "t.0001.png", "g8.exr", "h.0001.exr"})
            EXPECT_FALSE(fs::exists(path(name))) << name;
    }
    for (const auto& [file, bytes] : before)
        EXPECT_TRUE(slurp(file) == bytes) << file << " was changed";
    // Distinct outputs next to their inputs still work.
    EXPECT_EQ(run(light + " --plate " + path("plate.exr") + " -o " + path("out.exr")).status, 0);
}

// A frame pattern wider than the formatting buffer (31 digits) wrote every frame to one
// file, its name cut to zeros. Past 16 digits (frame numbers have at most 9 and a sign) a
// pattern is a usage error naming it; up to 16 every frame has its own file.
TEST_F(HostileInput, FramePatternWidthIsBounded) {
    ASSERT_EQ(
        run("dhdr-light " + path("g.exr") + " --lights " + kLights + " -o " + path("seq.1.exr"))
            .status,
        0);
    fs::copy_file(path("seq.1.exr"), path("seq.2.exr"));
    const std::string wide = path("wide." + std::string(40, '#') + ".exr");
    const std::string cases[] = {
        "dhdr-bloom " + path("seq.#.exr") + " -o " + wide,
        "dhdr-bloom " + path("seq.#.exr") + " -o " + path("wide.%040d.exr"),
        "dhdr-bloom " + path("seq.#.exr") + " -o " + path("wide.%099999999999999999999d.exr"),
        "dhdr-tonemap " + path("seq.#.exr") + " -o " + path("wide.%017d.png"),
        "dhdr-light " + path("g.exr") + " --lights " + kLights + " -o " + path("w.exr") +
            " --deep-out " + path("wide." + std::string(17, '#') + ".exr"),
    };
    for (const std::string& c : cases) {
        SCOPED_TRACE(c);
        const Result r = run(c);
        EXPECT_EQ(r.status, 2) << r.err;
        EXPECT_NE(r.err.find("the frame pattern is wider than 16 digits"), std::string::npos)
            << r.err;
        EXPECT_TRUE(noTemporaries());
    }
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().rfind("wide", 0), std::string::npos) << e.path();
    const Result r = run("dhdr-bloom " + path("seq.#.exr") + " -o " +
                         path("ok." + std::string(16, '#') + ".exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(path("ok.0000000000000001.exr")));
    EXPECT_TRUE(fs::exists(path("ok.0000000000000002.exr")));
}

// A 65536 × 65536 EXR whose pixels are really there (a constant image, ZIP-compressed to a few
// MB) streamed through dhdr-bloom or dhdr-tonemap for many minutes. Every tool now refuses an
// image of more than --max-pixels pixels (default 16384 × 16384) wherever it opens one —
// colour inputs, G-buffers flat and deep, --gbuffer, --plate, --channels — before any pixel is
// read or any output opened, and dhdr-gbuffer refuses such a --size; --max-pixels raises the
// limit (0 lifts it). A real 65536² file is too slow to make here: a 64 × 64 frame under
// --max-pixels 1000 stands in for it, and a header claiming 65536² for the default limit.
TEST_F(HostileInput, PixelLimitIsCheckedByEveryTool) {
    const std::string g64 = path("px_g64.exr"), gd64 = path("px_gd64.exr"),
                      h64 = path("px_h64.exr"), out = path("px_out.exr");
    const std::string lights = " --lights " + kLights;
    const std::string over = "64x64 pixels is more than --max-pixels 1000; give --max-pixels to "
                             "raise it";
    // dhdr-gbuffer: --size past the limit is a usage error.
    expectFailure(run("dhdr-gbuffer " + kCornell + " --size 64x64 --max-pixels 1000 -o " + g64), 2,
                  "--size 64x64: " + over, g64);
    ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 64x64 --max-pixels 4096 -o " + g64).status,
              0);
    ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 64x64 --deep -o " + gd64).status, 0);
    ASSERT_EQ(run("dhdr-light " + g64 + lights + " --aovs -o " + h64).status, 0);
    ASSERT_EQ(run("dhdr-light " + path("g.exr") + lights + " -o " + path("px_h.exr")).status, 0);
    struct Case {
        std::string command, file; // `file` is the one over the limit
        bool works = true;         // within the limit; else it fails for another reason
    };
    const Case cases[] = {
        {"dhdr-light " + g64 + lights, g64},
        {"dhdr-light " + gd64 + lights, gd64},
        // A dhdr G-buffer is not Blender's passes: within the limit, another complaint.
        {"dhdr-light " + g64 + lights + " --channels blender", g64, false},
        // The frame (32 × 24) is within the limit, its plate is not (nor of its size).
        {"dhdr-light " + path("g.exr") + lights + " --plate " + h64, h64, false},
        {"dhdr-aa " + h64, h64},
        {"dhdr-aa " + h64 + " --gbuffer " + g64, h64},
        {"dhdr-aa " + h64 + " --gbuffer " + gd64, h64},
        {"dhdr-aa " + path("px_h.exr") + " --gbuffer " + g64, g64, false},
        {"dhdr-aa " + path("px_h.exr") + " --gbuffer " + gd64, gd64, false},
        {"dhdr-bloom " + h64, h64},
        {"dhdr-tonemap " + h64, h64},
        {"dhdr-tonemap --op reinhard-local " + h64, h64},
        {"dhdr-tonemap --memory 0 " + h64, h64},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.command);
        expectFailure(run(c.command + " --max-pixels 1000 -o " + out), 1, c.file + ": " + over,
                      out);
        // At the limit, and with no limit, the same command works.
        for (const char* limit : {" --max-pixels 4096", " --max-pixels 0"}) {
            const Result r = run(c.command + limit + " -o " + out);
            if (c.works)
                EXPECT_EQ(r.status, 0) << limit << ": " << r.err;
            else
                EXPECT_EQ(r.err.find("--max-pixels"), std::string::npos) << limit << ": " << r.err;
            fs::remove(out);
        }
    }
    // Not a count of pixels: usage errors.
    for (const char* bad : {"-1", "1e9", "x", "99999999999999999999"})
        expectFailure(run("dhdr-bloom " + h64 + " --max-pixels " + std::string(bad) + " -o " + out),
                      2, "--max-pixels: '" + std::string(bad) + "' is not a count of pixels", out);
    // The default limit, 16384 × 16384, against a header that claims 65536 × 65536: refused at
    // once by every tool that reads an image, naming the file, its size and the limit.
    claimHugeSize(h64, path("px_huge.exr"), 65536);
    claimHugeSize(g64, path("px_huge_g.exr"), 65536);
    const std::string huge = "65536x65536 pixels is more than --max-pixels 268435456 "
                             "(16384x16384); give --max-pixels to raise it";
    const Case hugeCases[] = {
        {"dhdr-bloom " + path("px_huge.exr"), path("px_huge.exr")},
        {"dhdr-tonemap " + path("px_huge.exr"), path("px_huge.exr")},
        {"dhdr-aa " + path("px_huge.exr") + " --gbuffer " + g64, path("px_huge.exr")},
        {"dhdr-aa " + h64 + " --gbuffer " + path("px_huge_g.exr"), path("px_huge_g.exr")},
        {"dhdr-light " + path("px_huge_g.exr") + lights, path("px_huge_g.exr")},
    };
    for (const Case& c : hugeCases) {
        SCOPED_TRACE(c.command);
        const auto t = std::chrono::steady_clock::now();
        expectFailure(run(c.command + " -o " + out), 1, c.file + ": " + huge, out);
        EXPECT_LT(std::chrono::steady_clock::now() - t, std::chrono::seconds(10));
    }
    expectFailure(run("dhdr-gbuffer " + kCornell + " --size 65536x65536 -o " + out), 2,
                  "--size 65536x65536: " + huge, out);
    // A header of exactly 16384 × 16384 pixels passes the limit (and fails at its first absent
    // row, as before).
    claimHugeSize(h64, path("px_16k.exr"), 16384);
    const Result r = run("dhdr-tonemap " + path("px_16k.exr") + " -o " + out);
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err.find("--max-pixels"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("px_16k.exr: cannot read"), std::string::npos) << r.err;
}

// Names the tools wrote but could not read: a file whose name begins with '-' was taken for
// an option, and one whose name holds '?' was written but OpenImageIO could not open it.
// `--` now ends the options in every tool, and a file named with '*', '[', a space or a
// leading '-' goes through the whole chain — written by each tool, read back by the
// next (dhdr-gbuffer's G-buffer and --lights-out, dhdr-probes, dhdr-ibl, dhdr-light, dhdr-aa,
// dhdr-bloom, dhdr-tonemap) — run from the files' folder, as a user names them.
TEST_F(HostileInput, OddFileNamesGoThroughTheChain) {
    fs::copy_file(kCornell, path("scene.gltf"), fs::copy_options::overwrite_existing);
    for (const std::string stem : {"st*r", "br[1]", "sp ace", "-x", "--odd"}) {
        SCOPED_TRACE(stem);
        auto q = [&](const std::string& suffix) { return " '" + stem + suffix + "'"; };
        fs::copy_file(path("scene.gltf"), path(stem + ".gltf"));
        const std::string steps[] = {
            "dhdr-gbuffer --size 16x12 --lights-out" + q(".lights.json") + " -o" + q(".g.exr") +
                " --" + q(".gltf"),
            "dhdr-probes --grid 2,2,2 --lights" + q(".lights.json") + " -o" + q(".p.exr") + " --" +
                q(".gltf"),
            // A 2:1 picture for dhdr-ibl to bake.
            "dhdr-gbuffer --size 32x16 -o" + q(".eg.exr") + " --" + q(".gltf"),
            "dhdr-light --lights" + q(".lights.json") + " -o" + q(".env.exr") + " --" +
                q(".eg.exr"),
            "dhdr-ibl -o" + q(".ibl.exr") + " --" + q(".env.exr"),
            "dhdr-light --scene" + q(".gltf") + " --lights" + q(".lights.json") + " --lights" +
                q(".ibl.json") + " --probes" + q(".p.exr") + " -o" + q(".h.exr") + " --" +
                q(".g.exr"),
            "dhdr-aa --gbuffer" + q(".g.exr") + " -o" + q(".a.exr") + " --" + q(".h.exr"),
            "dhdr-bloom -o" + q(".b.exr") + " --" + q(".a.exr"),
            "dhdr-tonemap -o" + q(".png") + " --" + q(".b.exr"),
        };
        for (const std::string& step : steps) {
            if (step.find("dhdr-light --scene") == 0)
                std::ofstream(path(stem + ".ibl.json"))
                    << R"({"lights": [{"type": "environment", "intensity": 0.5, "image": )" << '"'
                    << stem << ".ibl.exr\"}]}";
            const Result r = runHere(step);
            ASSERT_EQ(r.status, 0) << step << ": " << r.err;
        }
        EXPECT_EQ(read(stem + ".png").spec().width, 16);
        EXPECT_TRUE(noTemporaries());
    }
    // '?': OpenImageIO takes what follows it in a name for options (file.exr?key=value) and
    // cannot open such a file, so no tool writes an image under such a name (a usage error
    // before anything is read) and one given as input is named with the reason. A lights
    // file (JSON) may still hold '?'.
    for (const char* c :
         {"dhdr-gbuffer --size 8x8 -o 'q?.g.exr' -- scene.gltf",
          "dhdr-bloom -o 'q?.b.exr' -- '-x.a.exr'", "dhdr-ibl -o 'q?.ibl.exr' -- '-x.env.exr'",
          "dhdr-probes --grid 2,2,2 -o 'q?.p.exr' -- scene.gltf",
          "dhdr-light --lights '-x.lights.json' -o x.exr --deep-out 'q?.d.exr' -- '-x.g.exr'"}) {
        SCOPED_TRACE(c);
        const Result r = runHere(c);
        EXPECT_EQ(r.status, 2) << r.err;
        EXPECT_NE(r.err.find("an image whose name holds '?' cannot be read back"),
                  std::string::npos)
            << r.err;
    }
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().rfind("q?", 0), std::string::npos) << e.path();
    fs::copy_file(path("-x.a.exr"), path("q?.a.exr"));
    const Result question = runHere("dhdr-bloom -o out.exr -- 'q?.a.exr'");
    EXPECT_EQ(question.status, 1) << question.err;
    EXPECT_NE(question.err.find("q?.a.exr: cannot read: OpenImageIO takes what follows '?'"),
              std::string::npos)
        << question.err;
    ASSERT_EQ(runHere("dhdr-gbuffer --size 8x8 --lights-out 'q?.lights.json' -o q.exr -- "
                      "scene.gltf")
                  .status,
              0);
    EXPECT_EQ(runHere("dhdr-light --lights 'q?.lights.json' -o q.h.exr -- q.exr").status, 0);
    // Without `--`, a name that begins with '-' is an unknown option; the message says what
    // to do.
    const Result r = runHere("dhdr-bloom -o out.exr -x.a.exr");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("unknown option -x.a.exr"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("after --"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("out.exr")));
    // After `--`, everything is a file, even a name spelt like an option.
    EXPECT_EQ(runHere("dhdr-bloom -o out.exr -- --help").status, 1);
    // A '#' in a file name stands for a digit of the frame number (docs/tools.md): `a#b.exr`
    // is a frame pattern, so a single picture cannot be written under that name (a usage
    // error that says why); with --frames it is a sequence.
    const Result hash = runHere("dhdr-bloom -o 'a#b.exr' -- '-x.a.exr'");
    EXPECT_EQ(hash.status, 2) << hash.err;
    EXPECT_NE(hash.err.find("a#b.exr"), std::string::npos) << hash.err;
    EXPECT_NE(hash.err.find("frame pattern"), std::string::npos) << hash.err;
    ASSERT_EQ(runHere("dhdr-gbuffer --size 8x8 --frames 3-3 -o 'a#b.exr' -- scene.gltf").status, 0);
    EXPECT_TRUE(fs::exists(path("a3b.exr")));
    EXPECT_EQ(
        runHere("dhdr-light --lights -x.lights.json --frames 3-3 -o 'c#d.exr' -- 'a#b.exr'").status,
        0);
    EXPECT_TRUE(fs::exists(path("c3d.exr")));
}

// Ranges were checked in double and the values used as float: --ao-distance 1e-50 passed
// (0, 1e30] and became 0, --bloom's --threshold 0.99999999999 passed [0, 1) and became 1,
// --key 1e-50 passed (0, 100] and became 0, --ground-plane and --background took 1e39 and
// became +Inf. Every option whose value ends in a float is now checked as that float, and the
// numbers of a lights file must be ones a float holds (0, or 1.4e-45 to 3.4e38 in magnitude).
TEST_F(HostileInput, FloatOptionsAreCheckedAsFloats) {
    const std::string g = path("g.exr"), h = path("fl_h.exr"), out = path("fl_out.exr");
    ASSERT_EQ(run("dhdr-light " + g + " --lights " + kLights + " --aovs -o " + h).status, 0);
    const std::string light = "dhdr-light " + g + " --lights " + kLights;
    struct Case {
        std::string command, message;
    };
    const Case cases[] = {
        {"dhdr-bloom " + h + " --key 1e-50", "--key: 1e-50 is outside (0, 100] as a float (0)"},
        {"dhdr-bloom " + h + " --threshold 0.99999999999",
         "--threshold: 0.99999999999 is outside [0, 1) as a float (1)"},
        {"dhdr-bloom " + h + " --sigma 1e39", "--sigma: 1e39 is outside [0, 64]"},
        {light + " --ao ssao --ao-distance 1e-50",
         "--ao-distance: 1e-50 is outside (0, 1e+30] as a float (0)"},
        {light + " --background 1e39,0,0", "--background: 1e39 is more than a float holds"},
        {"dhdr-aa " + h + " --normal-weight 1e39", "--normal-weight: 1e39 is outside [0, 1e+06]"},
        {"dhdr-gbuffer " + kCornell + " --size 8x8 --ground-plane 1e39",
         "--ground-plane: 1e39 is outside [-1e+30, 1e+30]"},
        {"dhdr-gbuffer " + kCornell + " --size 8x8 --ground-plane=-1e39",
         "--ground-plane: -1e39 is outside [-1e+30, 1e+30]"},
        {"dhdr-gbuffer " + kCornell + " --size 8x8 --lookat 1e39,0,0,0,0,0",
         "--lookat: 1e39 is more than a float holds"},
        {"dhdr-tonemap " + h + " --white 1e999", "--white must be a positive number"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.command);
        expectFailure(run(c.command + " -o " + out), 2, c.message, out);
    }
    // Values a float holds within the range still work.
    for (const std::string& ok : {"dhdr-bloom " + h + " --key 1e-30 --threshold 0.9999999",
                                  light + " --ao ssao --ao-distance 1e-30 --background 1e38,0,0,1",
                                  "dhdr-gbuffer " + kCornell + " --size 8x8 --ground-plane -1e30",
                                  "dhdr-aa " + h + " --normal-weight 1e-50"}) {
        SCOPED_TRACE(ok);
        const Result r = run(ok + " -o " + out);
        EXPECT_EQ(r.status, 0) << r.err;
        fs::remove(out);
    }
    // A lights file: 1e39 (refused before) and a non-zero number that a float rounds to 0.
    const std::string holds = "must be a number that a float holds (0, or 1.4e-45 to 3.4e38 in "
                              "magnitude)";
    std::ofstream(path("fl_big.json"))
        << R"([{"type": "point", "position": [0.28, 0.45, 0.28], "intensity": 1e39}])";
    std::ofstream(path("fl_tiny.json"))
        << R"([{"type": "point", "position": [0.28, 0.45, 0.28], "color": [1e-50, 1, 1]}])";
    std::ofstream(path("fl_range.json"))
        << R"([{"type": "point", "position": [0.28, 0.45, 0.28], "range": 1e-50}])";
    std::ofstream(path("fl_ok.json")) << R"([{"type": "point", "position": [0.28, 0.45, 0.28],
                                              "color": [1e-30, 1, 1], "range": 1e-44}])";
    const std::string lit = "dhdr-light " + g + " -o " + out + " --lights ";
    expectFailure(run(lit + path("fl_big.json")), 1, "fl_big.json: light 0: \"intensity\" " + holds,
                  out);
    expectFailure(run(lit + path("fl_tiny.json")), 1,
                  "fl_tiny.json: light 0: \"color\" must be an array of 3 numbers that a float "
                  "holds",
                  out);
    expectFailure(run(lit + path("fl_range.json")), 1, "fl_range.json: light 0: \"range\" " + holds,
                  out);
    EXPECT_EQ(run(lit + path("fl_ok.json")).status, 0);
}

// The EXR headers the fuzzers found (tests/fuzz_regressions): a string attribute claiming 2 GB
// in a 205-byte file made every tool allocate it (2 GB of memory), and a channel of an unknown
// pixel type aborted the process inside OpenImageIO. Every tool now refuses them by name,
// exit 1, before OpenEXR reads them.
TEST_F(HostileInput, ExrHeadersThatLieAreRefusedByEveryTool) {
    ASSERT_EQ(run("dhdr-light " + path("g.exr") + " --lights " + kLights + " -o " + path("lit.exr"))
                  .status,
              0);
    const std::string regressions = kTestdata + "/../tests/fuzz_regressions/fuzz_gbuffer/";
    for (const char* name :
         {"openexr-string-attribute-2gb.exr", "oiio-abort-unknown-pixel-type.exr",
          "openexr-chlist-shorter-than-its-size.exr"}) {
        const std::string bad = regressions + name;
        ASSERT_TRUE(fs::exists(bad)) << bad;
        for (const std::string& cmd : {"dhdr-bloom " + bad, "dhdr-tonemap " + bad,
                                       "dhdr-aa " + bad + " --gbuffer " + path("g.exr"),
                                       "dhdr-aa " + path("lit.exr") + " --gbuffer " + bad,
                                       "dhdr-light " + bad + " --lights " + kLights}) {
            SCOPED_TRACE(cmd);
            const Result r = run(cmd + " -o " + path("out.exr"));
            EXPECT_EQ(r.status, 1) << r.err;
            EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
            EXPECT_FALSE(fs::exists(path("out.exr")));
        }
    }
    EXPECT_TRUE(noTemporaries());
}
