// The params tables (dhdr/common/param_table.h) against what depends on them: validate()
// refuses exactly what is outside each range, the tools refuse it as usage errors and show it
// in --help, and the docs' option tables state the same ranges.
#include "tool_test.h"

#include <dhdr/deferred/direct/ambient_occlusion.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <fstream>

using namespace dhdr;
using namespace dhdr::test;

namespace {

// The row of `doc`'s option tables for `option` ("| `--rays N` | …"); empty when none.
std::string docRow(const std::string& doc, const std::string& option, const std::string& metavar) {
    std::ifstream in(kTestdata + "/../docs/" + doc);
    EXPECT_TRUE(in) << doc;
    const std::string start = "| `" + option + " " + metavar + "` |";
    for (std::string line; std::getline(in, line);)
        if (line.rfind(start, 0) == 0) return line;
    return {};
}

std::string range(int lo, int hi) {
    return "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
}

template <class Params, size_t N>
void checkTable(const IntParam<Params> (&table)[N], const std::string& doc) {
    for (const IntParam<Params>& p : table) {
        SCOPED_TRACE(p.option);
        Params params;
        params.*(p.field) = p.min;
        EXPECT_EQ(checkRanges(params, table), "");
        params.*(p.field) = p.max;
        EXPECT_EQ(checkRanges(params, table), "");
        params.*(p.field) = p.min - 1;
        EXPECT_NE(checkRanges(params, table).find(p.option), std::string::npos);
        params.*(p.field) = p.max + 1;
        EXPECT_NE(checkRanges(params, table).find(p.option), std::string::npos);
        const std::string row = docRow(doc, p.option, p.metavar);
        ASSERT_FALSE(row.empty()) << "docs/" << doc << " has no row for " << p.option;
        EXPECT_NE(row.find(range(p.min, p.max)), std::string::npos)
            << "docs/" << doc << " states another range than " << range(p.min, p.max) << ":\n"
            << row;
    }
}

class Params : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }
};

} // namespace

TEST_F(Params, DocsStateTheTablesRanges) {
    checkTable(kLightingParamTable, "tools.md");
    checkTable(kSsaoParamTable, "tools.md");
    checkTable(kProbeBakeParamTable, "gi.md");
}

// The library refuses what the table refuses, naming the option.
TEST_F(Params, ValidateNamesTheFieldOutOfRange) {
    LightingParams p;
    std::string error;
    EXPECT_TRUE(validate(p, error)) << error;
    p.shadowSamples = 5000;
    EXPECT_FALSE(validate(p, error));
    EXPECT_NE(error.find("--shadow-samples"), std::string::npos) << error;
    p = LightingParams{};
    p.aoDistance = 0.0f;
    EXPECT_FALSE(validate(p, error));
}

// Each tool takes exactly the table's range (no silent cut: --ao-samples 300 with --ao ssao
// was cut to 256) and shows it in --help.
TEST_F(Params, ToolsRefuseWhatTheTablesRefuseAndShowTheRange) {
    const std::string g = path("g.exr");
    ASSERT_EQ(run("dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --size 8x8 -o " + g).status, 0);
    const std::string lights = " --lights " + kTestdata + "/cornell_box.lights.json";
    const Result help = run("dhdr-light --help");
    for (const IntParam<LightingParams>& p : kLightingParamTable) {
        SCOPED_TRACE(p.option);
        EXPECT_NE(help.out.find(range(p.min, p.max)), std::string::npos) << help.out;
        const Result over = run("dhdr-light " + g + lights + " " + p.option + " " +
                                std::to_string(p.max + 1) + " -o " + path("x.exr"));
        EXPECT_EQ(over.status, 2) << over.err;
        EXPECT_FALSE(fs::exists(path("x.exr")));
    }
    const Result ssao =
        run("dhdr-light " + g + lights + " --ao ssao --ao-samples 300 -o " + path("x.exr"));
    EXPECT_EQ(ssao.status, 2) << ssao.err;
    EXPECT_NE(ssao.err.find("1-256"), std::string::npos) << ssao.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
    const Result probes = run("dhdr-probes --help");
    for (const IntParam<ProbeBakeParams>& p : kProbeBakeParamTable)
        EXPECT_NE(probes.out.find(range(p.min, p.max)), std::string::npos) << p.option;
}
