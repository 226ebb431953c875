// The inputs of past fuzzing crashes (tests/fuzz_regressions/<target>/) and the fuzzers' seeds
// (fuzz/corpus/<target>/) replayed through the very calls of the libFuzzer targets
// (fuzz/targets.h; docs/development.md, "Fuzzing"): none may crash, and under `make sanitize`
// none may make a sanitizer report. The tests after the replay say what each fixed input must
// now give.
#include "../fuzz/targets.h"

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

} // namespace
