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
#include <dhdr/deferred/scene/animation.h>
#include <dhdr/deferred/scene/scene_camera.h>
#include <dhdr/tonemap/adaptation.h>
#include <dhdr/tonemap/bloom.h>
#include <dhdr/tonemap/edge_aa.h>
#include <dhdr/tonemap/luminance.h>
#include <dhdr/tonemap/metering.h>
#include <dhdr/tonemap/motion_blur.h>
#include <dhdr/tonemap/tone_map.h>
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
// range and the default, and a value just outside the range is a usage error. A row whose help
// gives its default in words (0: the scene camera's) has the docs give it in words too.
template <class Params, class T, size_t N>
void checkFloatTable(const FloatParam<Params, T> (&table)[N], const std::string& doc,
                     const std::string& helpText) {
    for (const FloatParam<Params, T>& p : table) {
        SCOPED_TRACE(p.option);
        Params params;
        EXPECT_EQ(checkRanges(params, table), "") << "the default is outside the range";
        params.*(p.field) = T(p.range.hi * 2.0 + 1.0);
        EXPECT_NE(checkRanges(params, table).find(p.option), std::string::npos);
        EXPECT_NE(checkRanges(params, table, Spelling::Keyword).find(p.keyword), std::string::npos);
        const std::string row = docRow(doc, p.option, p.metavar);
        ASSERT_FALSE(row.empty()) << "docs/" << doc << " has no row for " << p.option;
        EXPECT_NE(row.find(p.range.text()), std::string::npos) << row;
        if (std::string(p.help).find("default") != std::string::npos) {
            EXPECT_NE(row.find("default"), std::string::npos) << row;
            EXPECT_NE(helpText.find(std::string(p.help) + " " + p.range.text()), std::string::npos)
                << helpText;
            continue;
        }
        const std::string dflt = "(default " + number(double(Params{}.*(p.field))) + ")";
        EXPECT_NE(row.find(dflt), std::string::npos) << row;
        EXPECT_NE(helpText.find(dflt + " " + p.range.text()), std::string::npos) << helpText;
    }
}

// A choice table against its docs' rows (the names, the default) and its tool's help; every
// name sets its index and any other is refused naming the keyword.
template <class Params, size_t N>
void checkChoiceTable(const ChoiceParam<Params> (&table)[N], const std::string& doc,
                      const std::string& helpText) {
    const Params defaults;
    for (const ChoiceParam<Params>& p : table) {
        SCOPED_TRACE(p.option);
        std::string names = p.names;
        for (size_t i = names.find('|'); i != std::string::npos; i = names.find('|', i + 2))
            names.replace(i, 1, "\\|");
        const std::string row = docRow(doc, p.option, names);
        ASSERT_FALSE(row.empty()) << "no docs row";
        const std::string dflt = "(default " + choiceName(p.names, p.get(defaults)) + ")";
        EXPECT_NE(row.find(dflt), std::string::npos) << row;
        EXPECT_NE(helpText.find(p.option + std::string(" ") + p.names), std::string::npos);
        Params o;
        std::string error;
        EXPECT_FALSE(setChoice(p, o, "nonsense", Spelling::Keyword, error));
        EXPECT_NE(error.find(p.keyword), std::string::npos) << error;
        for (int i = 0; !choiceName(p.names, i).empty(); ++i) {
            ASSERT_TRUE(setChoice(p, o, choiceName(p.names, i), Spelling::Option, error));
            EXPECT_EQ(p.get(o), i);
        }
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
    checkTable(kMomentIntTable, "tools.md");
}

// The float tables, the choices and flags: docs, --help and the tables agree.
TEST_F(Params, FloatTablesAndChoicesAgreeWithDocsAndHelp) {
    checkFloatTable(kBloomFloatTable, "tools.md", run("dhdr-bloom --help").out);
    checkFloatTable(kMotionBlurFloatTable, "tools.md", run("dhdr-motionblur --help").out);
    checkFloatTable(kEdgeAAFloatTable, "tools.md", run("dhdr-aa --help").out);
    const std::string light = run("dhdr-light --help").out;
    checkFloatTable(kLightingFloatTable, "tools.md", light);
    checkChoiceTable(kLightingChoiceTable, "tools.md", light);
    const std::string gbuffer = run("dhdr-gbuffer --help").out;
    checkChoiceTable(kGBufferChoiceTable, "tools.md", gbuffer);
    checkFloatTable(kGBufferFloatTable, "tools.md", gbuffer);
    for (const FlagParam<LightingOptions>& p : kLightingFlagTable)
        EXPECT_NE(light.find(p.option), std::string::npos) << p.option;
    const std::string tonemap = run("dhdr-tonemap --help").out;
    checkFloatTable(kToneMapFloatTable, "tools.md", tonemap);
    checkFloatTable(kLuminanceFloatTable, "tools.md", tonemap);
    checkFloatTable(kAdaptationFloatTable, "tools.md", tonemap);
    checkChoiceTable(kToneMapChoiceTable, "tools.md", tonemap);
    checkFloatTable(kMomentFloatTable, "tools.md", gbuffer);
    checkFloatTable(kCameraFloatTable, "tools.md", gbuffer);
    checkFloatTable(kProbeBakeFloatTable, "gi.md", run("dhdr-probes --help").out);
}

// The grid's counts: each given one within [1, 256], all 0 (not given) passing the library's
// check, and the docs, the tool and the Python keyword's message stating the range.
TEST_F(Params, ProbeGridTableAgreesWithDocsHelpAndTool) {
    for (const IntVecParam<ProbeBakeParams, glm::ivec3>& p : kProbeGridTable) {
        const std::string text = range(p.min, p.max);
        ProbeBakeParams params;
        EXPECT_EQ(checkRanges(params, kProbeGridTable), "");
        params.counts = glm::ivec3(p.min, p.max, 2);
        EXPECT_EQ(checkRanges(params, kProbeGridTable), "");
        params.counts = glm::ivec3(0, 2, 2);
        EXPECT_EQ(checkRanges(params, kProbeGridTable, Spelling::Keyword),
                  "grid: 0,2,2 has a number outside " + text);
        EXPECT_NE(rangeProblem(p, glm::ivec3(0), Spelling::Option), "") << "given, 0 is out";
        EXPECT_NE(docRow("gi.md", p.option, p.metavar).find(text), std::string::npos);
        EXPECT_NE(run("dhdr-probes --help").out.find(text), std::string::npos);
        const Result over = run("dhdr-probes " + kTestdata + "/cornell_box.gltf --grid 2,2," +
                                std::to_string(p.max + 1) + " -o " + path("x.exr"));
        EXPECT_EQ(over.status, 2) << over.err;
        EXPECT_NE(over.err.find(text), std::string::npos) << over.err;
    }
}

// The histogram metering's window, one rule for dhdr-tonemap and dhdr.meter()/tone_map().
TEST_F(Params, PercentileWindowIsOneRule) {
    MeteringParams m;
    EXPECT_EQ(percentilesProblem(m, Spelling::Option), "");
    m.lowPercentile = 0.0;
    m.highPercentile = 100.0;
    EXPECT_EQ(percentilesProblem(m, Spelling::Option), "");
    m.lowPercentile = 90.0;
    m.highPercentile = 10.0;
    EXPECT_EQ(percentilesProblem(m, Spelling::Keyword),
              "percentiles must be (LO, HI) with 0 <= LO < HI <= 100");
    const std::string message = percentilesProblem(m, Spelling::Option);
    for (const char* window : {"90,10", "-1,50", "5,101", "5"}) {
        const Result r = run("dhdr-tonemap " + path("in.exr") + " --metering histogram " +
                             "--percentiles " + window + " -o " + path("x.png"));
        EXPECT_EQ(r.status, 2) << window;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    }
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
