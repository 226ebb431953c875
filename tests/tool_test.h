// Running the tools as a user runs them, for the tool-level tests: a scratch folder, the
// command's exit status and output, pictures read back.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace dhdr::test {

namespace fs = std::filesystem;
using OIIO::ImageBuf;

// The build tree's tools; $DHDR_TOOLS_DIR runs the same tests against other builds (an older
// commit's, to see a test fail before its fix).
inline const std::string kTools =
    std::getenv("DHDR_TOOLS_DIR") ? std::getenv("DHDR_TOOLS_DIR") : DHDR_TOOLS_DIR;
inline const std::string kTestdata = DHDR_TESTDATA;

struct Result {
    int status = -1;
    std::string out, err;
};

inline std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A test suite with one scratch folder for all its tests, removed at the end.
class ToolTest : public ::testing::Test {
protected:
    static inline fs::path dir;

    static void makeScratch() {
        char pattern[] = "/tmp/dhdr_tools_XXXXXX";
        dir = mkdtemp(pattern);
    }
    static void TearDownTestSuite() { fs::remove_all(dir); }

    // The inputs every test of a suite reads (a G-buffer, a lit frame), which `make` writes
    // into the scratch folder. ctest runs each test case as a process of its own, so a suite's
    // setup ran the tools again for every test. Under ctest a fixture test
    // (tests/CMakeLists.txt, dhdr_shared_inputs) runs `make` once per run with
    // $DHDR_SHARED_INPUTS_MAKE set and keeps what it wrote in $DHDR_SHARED_INPUTS, and every
    // other test copies those files into its own scratch folder. Run by hand, with neither
    // variable, a test makes its own.
    template <class Make>
    static void sharedInputs(Make make) {
        const char* shared = std::getenv("DHDR_SHARED_INPUTS");
        if (!shared) {
            make();
            return;
        }
        const fs::path store(shared);
        if (std::getenv("DHDR_SHARED_INPUTS_MAKE")) {
            fs::remove_all(store);
            make();
            fs::create_directories(store);
            for (const auto& e : fs::directory_iterator(dir))
                if (e.is_regular_file()) fs::copy_file(e.path(), store / e.path().filename());
            return;
        }
        ASSERT_TRUE(fs::is_directory(store))
            << store << " is missing: its fixture test did not run or failed";
        for (const auto& e : fs::directory_iterator(store))
            fs::copy_file(e.path(), dir / e.path().filename(),
                          fs::copy_options::overwrite_existing);
    }

    static std::string path(const std::string& name) { return (dir / name).string(); }

    // Runs `args` (a tool name and its arguments) from the build tree.
    static Result run(const std::string& args) {
        Result r;
        // The tools' defaults (the built-in OCIO config) whatever the caller's environment.
        const std::string cmd = "env -u OCIO " + kTools + "/" + args + " >" + path("stdout.txt") +
                                " 2>" + path("stderr.txt") + " </dev/null";
        const int raw = std::system(cmd.c_str());
        r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
        r.out = slurp(dir / "stdout.txt");
        r.err = slurp(dir / "stderr.txt");
        return r;
    }

    // Channel `name` of pixel (x, y) of a flat float image read with read(); NaN (and a
    // failure) where the image has no such channel.
    static float channel(const ImageBuf& g, int x, int y, const char* name) {
        const int c = g.spec().channelindex(name);
        EXPECT_GE(c, 0) << name;
        return c < 0 ? NAN : static_cast<const float*>(g.pixeladdr(x, y))[c];
    }

    // A copy of the EXR `from` whose header claims a `size` × `size` image: its dataWindow and
    // displayWindow rewritten in place, room for the line offset table appended, the pixels
    // as they were (absent for most rows).
    static void claimHugeSize(const std::string& from, const std::string& to, int size) {
        std::string bytes = slurp(from);
        for (const char* name : {"dataWindow", "displayWindow"}) {
            const std::string key = std::string(name) + '\0' + "box2i" + '\0';
            const size_t at = bytes.find(key);
            ASSERT_NE(at, std::string::npos) << name;
            const int box[4] = {0, 0, size - 1, size - 1};
            std::memcpy(&bytes[at + key.size() + 4], box, sizeof box);
        }
        bytes.append(size_t(size) * 8, '\0');
        std::ofstream(to, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    }

    static bool noTemporaries() {
        for (const auto& e : fs::directory_iterator(dir))
            if (e.path().filename().string().find(".tmp") != std::string::npos) return false;
        return true;
    }

    static ImageBuf read(const std::string& name) {
        ImageBuf img(path(name));
        img.read(0, 0, true, OIIO::TypeDesc::FLOAT);
        return img;
    }

    static bool allFinite(const ImageBuf& img) {
        const float* p = static_cast<const float*>(img.localpixels());
        for (size_t i = 0; i < img.spec().image_pixels() * size_t(img.nchannels()); ++i)
            if (!std::isfinite(p[i])) return false;
        return true;
    }
};

} // namespace dhdr::test
