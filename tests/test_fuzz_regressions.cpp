// The inputs of past fuzzing crashes (tests/fuzz_regressions/<target>/) and the fuzzers' seeds
// (fuzz/corpus/<target>/) replayed through the very calls of the libFuzzer targets
// (fuzz/targets.h; docs/development.md, "Fuzzing"): none may crash, and under `make sanitize`
// none may make a sanitizer report. The tests after the replay say what each fixed input must
// now give.
#include "../fuzz/targets.h"

#include <OpenImageIO/imagebuf.h>
#include <dhdr/deferred/environment.h>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <iterator>

namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> readBytes(const fs::path& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

std::vector<fs::path> inputsOf(const std::string& target) {
    std::vector<fs::path> files;
    for (const fs::path dir : {fs::path(DHDR_SOURCE_DIR) / "fuzz" / "corpus" / target,
                               fs::path(DHDR_SOURCE_DIR) / "tests" / "fuzz_regressions" / target})
        if (fs::is_directory(dir))
            for (const auto& e : fs::directory_iterator(dir))
                if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

class FuzzReplay : public ::testing::TestWithParam<dhdr::fuzz::Target> {};

TEST_P(FuzzReplay, EverySeedAndPastCrashRunsCleanly) {
    dhdr::fuzz::initImageLibraries();
    const dhdr::fuzz::Target& t = GetParam();
    const std::vector<fs::path> files = inputsOf(t.name);
    EXPECT_FALSE(files.empty()) << "no seeds for " << t.name;
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        const std::vector<uint8_t> bytes = readBytes(file);
        t.run(bytes.data(), bytes.size());
    }
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzReplay, ::testing::ValuesIn(dhdr::fuzz::kTargets),
                         [](const auto& info) { return std::string(info.param.name); });

// Writes a width × height environment of `nch` channels whose every value is `value`.
void writeEnvironment(const std::string& path, int width, int height, int nch, float value) {
    OIIO::ImageSpec spec(width, height, nch, OIIO::TypeDesc::FLOAT);
    if (nch == 2) spec.channelnames = {"Y", "A"};
    std::vector<float> pixels(size_t(width) * size_t(height) * size_t(nch), value);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close());
}

// fuzz_ibl, its first seeds in a row: readEnvironmentImage checked the header it opened, then
// read the pixels through an ImageBuf, whose header came from OpenImageIO's shared ImageCache:
// for a path read before and since rewritten larger, the old, smaller one. The loop over the
// new size overran the old buffer (AddressSanitizer: heap-buffer-overflow in
// environment.cpp). An environment rewritten between two reads is read as it is now.
TEST(FuzzRegressions, EnvironmentRewrittenLargerBetweenTwoReadsIsReadAsItIsNow) {
    const std::string path = (fs::temp_directory_path() /
                              ("dhdr-fuzz-regression-env-" + std::to_string(::getpid()) + ".exr"))
                                 .string();
    writeEnvironment(path, 8, 4, 2, 0.25f);
    dhdr::EnvironmentImage env;
    std::string error;
    ASSERT_TRUE(dhdr::readEnvironmentImage(path, env, error)) << error;
    EXPECT_EQ(env.width, 8);
    // The shared ImageCache now knows the path as 8x4, two channels.
    OIIO::ImageBuf cached(path);
    ASSERT_TRUE(cached.init_spec(path, 0, 0));
    writeEnvironment(path, 16, 8, 3, 2.0f);
    ASSERT_TRUE(dhdr::readEnvironmentImage(path, env, error)) << error;
    EXPECT_EQ(env.width, 16);
    EXPECT_EQ(env.height, 8);
    ASSERT_EQ(env.rgb.size(), size_t(16 * 8 * 3));
    for (const float v : env.rgb)
        ASSERT_EQ(v, 2.0f);
    fs::remove(path);
}

} // namespace
