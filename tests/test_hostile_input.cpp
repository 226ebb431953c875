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
        ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 32x24 -o " + path("g.exr")).status, 0);
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
