// The params tables (dhdr/common/param_table.h) against what depends on them: validate()
// refuses exactly what is outside each range, the tools refuse it as usage errors and show it
// in --help, and the docs' option tables state the same ranges.
#include "tool_test.h"

#include <dhdr/deferred/direct/ambient_occlusion.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/integrator/lighting_options.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/tonemap/bloom.h>
#include <dhdr/tonemap/edge_aa.h>
#include <dhdr/tonemap/motion_blur.h>
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

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

// A float table against its docs' rows (range and default) and its tool: the help states the
// range and the default, and a value just outside the range is a usage error.
template <class Params, size_t N>
void checkFloatTable(const FloatParam<Params> (&table)[N], const std::string& doc,
                     const std::string& helpText) {
    for (const FloatParam<Params>& p : table) {
        SCOPED_TRACE(p.option);
        Params params;
        EXPECT_EQ(checkRanges(params, table), "") << "the default is outside the range";
        params.*(p.field) = float(p.range.hi) * 2.0f + 1.0f;
        EXPECT_NE(checkRanges(params, table).find(p.option), std::string::npos);
        EXPECT_NE(checkRanges(params, table, Spelling::Keyword).find(p.keyword), std::string::npos);
        const std::string row = docRow(doc, p.option, p.metavar);
        ASSERT_FALSE(row.empty()) << "docs/" << doc << " has no row for " << p.option;
        const std::string dflt = "(default " + number(double(Params{}.*(p.field))) + ")";
        EXPECT_NE(row.find(p.range.text()), std::string::npos) << row;
        EXPECT_NE(row.find(dflt), std::string::npos) << row;
        EXPECT_NE(helpText.find(dflt + " " + p.range.text()), std::string::npos) << helpText;
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
    checkTable(kGBufferParamTable, "tools.md");
    checkTable(kIblBakeParamTable, "tools.md");
}

// The library refuses what the table refuses, naming the option.
// The float tables, the lighting choices and flags: docs, --help and the tables agree.
TEST_F(Params, FloatTablesAndChoicesAgreeWithDocsAndHelp) {
    checkFloatTable(kBloomFloatTable, "tools.md", run("dhdr-bloom --help").out);
    checkFloatTable(kMotionBlurFloatTable, "tools.md", run("dhdr-motionblur --help").out);
    checkFloatTable(kEdgeAAFloatTable, "tools.md", run("dhdr-aa --help").out);
    const std::string light = run("dhdr-light --help").out;
    checkFloatTable(kLightingFloatTable, "tools.md", light);
    const LightingOptions defaults;
    for (const ChoiceParam<LightingOptions>& p : kLightingChoiceTable) {
        SCOPED_TRACE(p.option);
        std::string names = p.names;
        for (size_t i = names.find('|'); i != std::string::npos; i = names.find('|', i + 2))
            names.replace(i, 1, "\\|");
        ASSERT_FALSE(docRow("tools.md", p.option, names).empty()) << "no docs row";
        const std::string dflt = "(default " + choiceName(p.names, p.get(defaults)) + ")";
        EXPECT_NE(docRow("tools.md", p.option, names).find(dflt), std::string::npos);
        EXPECT_NE(light.find(p.option + std::string(" ") + p.names), std::string::npos);
        LightingOptions o;
        std::string error;
        EXPECT_FALSE(setChoice(p, o, "nonsense", Spelling::Keyword, error));
        EXPECT_NE(error.find(p.keyword), std::string::npos) << error;
        for (int i = 0; !choiceName(p.names, i).empty(); ++i) {
            ASSERT_TRUE(setChoice(p, o, choiceName(p.names, i), Spelling::Option, error));
            EXPECT_EQ(p.get(o), i);
        }
    }
    for (const FlagParam<LightingOptions>& p : kLightingFlagTable)
        EXPECT_NE(light.find(p.option), std::string::npos) << p.option;
}

// The rules between the lighting choices, in each spelling.
TEST_F(Params, LightingRulesAreSpelledForTheirCaller) {
    LightingParams params;
    SsaoParams ssao;
    std::string error;
    LightingOptions o;
    o.params.pathSamples = 4;
    EXPECT_FALSE(resolveLighting(o, {true, true, false}, Spelling::Option, params, ssao, error));
    EXPECT_EQ(error, "--spp and --path-bounces are for --gi path");
    EXPECT_FALSE(resolveLighting(o, {true, true, false}, Spelling::Keyword, params, ssao, error));
    EXPECT_EQ(error, "spp and path_bounces are for gi='path'");
    o = LightingOptions{};
    o.ao = AoMode::RayTraced;
    EXPECT_FALSE(resolveLighting(o, {true, false, false}, Spelling::Option, params, ssao, error));
    EXPECT_EQ(error, "--ao rt traces rays in the scene: give --scene SCENE");
    EXPECT_TRUE(resolveLighting(o, {true, true, false}, Spelling::Option, params, ssao, error));
    EXPECT_EQ(params.aoSamples, 16);
    o.ao = AoMode::ScreenSpace;
    EXPECT_TRUE(resolveLighting(o, {true, true, false}, Spelling::Option, params, ssao, error));
    EXPECT_EQ(params.aoSamples, 0);
    EXPECT_EQ(ssao.samples, 16);
    EXPECT_EQ(deepGBufferProblem(o, Spelling::Keyword),
              "ao='ssao' works on flat G-buffers; a deep one needs ao='rt'");
    o = LightingOptions{};
    o.params.pathTrace = true;
    o.params.denoise = true;
    EXPECT_FALSE(resolveLighting(o, {true, true, true}, Spelling::Keyword, params, ssao, error));
    EXPECT_EQ(error, "gi='path' computes the indirect light itself: drop probes");
    EXPECT_TRUE(resolveLighting(o, {true, true, false}, Spelling::Keyword, params, ssao, error));
    EXPECT_FALSE(params.denoise) << "the reference path tracer is never denoised";
    EXPECT_FALSE(resolveLighting(LightingOptions{}, {false, false, false}, Spelling::Option, params,
                                 ssao, error));
    EXPECT_EQ(error, "no lights: give --lights FILE, or --scene SCENE for the scene's own");
}

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
    EXPECT_NE(ssao.err.find(range(1, 256)), std::string::npos) << ssao.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
    const Result probes = run("dhdr-probes --help");
    for (const IntParam<ProbeBakeParams>& p : kProbeBakeParamTable)
        EXPECT_NE(probes.out.find(range(p.min, p.max)), std::string::npos) << p.option;
}
