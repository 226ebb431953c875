// The colour management of dhdr-tonemap against OpenColorIO's own processors and closed forms.
#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/imagebuf.h>
#include <cmath>
#include <cstdlib>
#include <dhdr/tonemap/display_transform.h>
#include <dhdr/tonemap/tone_map.h>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

namespace OCIO = OCIO_NAMESPACE;
using namespace dhdr;
using OIIO::ImageBuf;

namespace {

ImageBuf row(const std::vector<float>& rgb) {
    ImageBuf img(OIIO::ImageSpec(int(rgb.size() / 3), 1, 3, OIIO::TypeDesc::FLOAT));
    std::copy(rgb.begin(), rgb.end(), static_cast<float*>(img.localpixels()));
    return img;
}

const float* px(const ImageBuf& img, int x) {
    return static_cast<const float*>(img.pixeladdr(x, 0));
}

// The sRGB opto-electronic transfer function, IEC 61966-2-1, in double.
double srgbEncode(double v) {
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

// Its inverse, IEC 61966-2-1 in double.
double srgbDecode(double e) {
    return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

struct NoOcioEnv : ::testing::Test {
    void SetUp() override { unsetenv("OCIO"); }
};

} // namespace

TEST_F(NoOcioEnv, BuiltinStandardViewIsTheSrgbEncoding) {
    DisplayTransform display;
    std::string error;
    ASSERT_TRUE(display.init({}, error)) << error;
    EXPECT_EQ(display.describe(), "sRGB / Standard (built-in config)");
    EXPECT_EQ(display.outputColorSpace(), "sRGB"); // its "sRGB - Display"
    const std::vector<float> v = {0.0f, 0.002f, 0.01f, 0.18f, 0.5f, 0.9f};
    std::vector<float> rgb;
    for (float x : v)
        rgb.insert(rgb.end(), {x, x, x});
    ImageBuf img = row(rgb);
    ASSERT_TRUE(display.toDisplay(img));
    // Linear Rec.709 → ACES → XYZ → sRGB is the sRGB transfer function, to float rounding of
    // the primaries' round trip.
    for (size_t i = 0; i < v.size(); ++i)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(px(img, int(i))[c], srgbEncode(v[i]), 2e-4) << v[i];
    // The published points: the linear segment's end, and mid-grey of the encoding.
    EXPECT_NEAR(srgbEncode(0.0031308), 0.04045, 1e-6);
    EXPECT_NEAR(srgbEncode(0.5), 0.735357, 1e-6);
}

TEST_F(NoOcioEnv, AcesOperatorEqualsOpenColorIOsOutputTransform) {
    // The same chain assembled here from OpenColorIO's built-in transforms.
    OCIO::GroupTransformRcPtr chain = OCIO::GroupTransform::Create();
    auto add = [&](const char* style, bool inverse) {
        OCIO::BuiltinTransformRcPtr t = OCIO::BuiltinTransform::Create();
        t->setStyle(style);
        if (inverse) t->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
        chain->appendTransform(t);
    };
    add("UTILITY - ACES-AP1_to_LINEAR-REC709_BFD", true);
    add("ACEScg_to_ACES2065-1", false);
    add("ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 - SDR-VIDEO_1.0", false);
    add("DISPLAY - CIE-XYZ-D65_to_sRGB", false);
    const auto cpu = OCIO::Config::CreateRaw()->getProcessor(chain)->getDefaultCPUProcessor();

    const std::vector<float> rgb = {0.02f, 0.02f, 0.02f, 0.18f, 0.1f, 0.05f,
                                    1.0f,  2.0f,  0.5f,  8.0f,  8.0f, 8.0f};
    // Metering that makes the operator's scale 1: its output is the input, scene-linear.
    LuminanceStats stats;
    stats.logAverage = 0.18;
    ToneMapParams p;
    p.op = ToneOperator::Aces;
    p.stats = &stats;
    ImageBuf mapped;
    ASSERT_TRUE(toneMap(mapped, row(rgb), p));
    DisplayTransform display;
    DisplaySettings settings;
    settings.view = "ACES";
    std::string error;
    ASSERT_TRUE(display.init(settings, error)) << error;
    ASSERT_TRUE(display.toDisplay(mapped));
    for (size_t i = 0; i < rgb.size() / 3; ++i) {
        float ref[3] = {rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]};
        cpu->applyRGB(ref);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(px(mapped, int(i))[c], ref[c], 1e-5) << i;
    }
    // A tone curve, not the identity: mid grey lands below its sRGB encoding.
    EXPECT_LT(px(mapped, 0)[0], srgbEncode(0.02));
}

TEST_F(NoOcioEnv, UnknownNamesListTheValidOnes) {
    DisplayTransform display;
    std::string error;
    DisplaySettings s;
    s.view = "Filmic";
    EXPECT_FALSE(display.init(s, error));
    EXPECT_EQ(error, "unknown view 'Filmic' of display 'sRGB' (it has: Standard, ACES)");
    s = {};
    s.display = "P3";
    EXPECT_FALSE(display.init(s, error));
    EXPECT_EQ(error, "unknown display 'P3' (built-in config has: sRGB)");
    s = {};
    s.colorspace = "Log";
    EXPECT_FALSE(display.init(s, error));
    EXPECT_NE(error.find("unknown colour space 'Log' (built-in config has: ACES2065-1, ACEScg"),
              std::string::npos);
}

TEST_F(NoOcioEnv, V1AndV2ConfigsByPathOrEnvironment) {
    // An OCIO v1 config: linear in, a gamma 2.2 view.
    const auto path = std::filesystem::temp_directory_path() / "dhdr_test_v1.ocio";
    std::ofstream(path) << R"(ocio_profile_version: 1
roles:
  scene_linear: linear
  default: linear
displays:
  Monitor:
    - !<View> {name: Gamma, colorspace: gamma22}
    - !<View> {name: Raw, colorspace: linear}
active_displays: [Monitor]
active_views: [Gamma, Raw]
colorspaces:
  - !<ColorSpace>
    name: linear
    bitdepth: 32f
  - !<ColorSpace>
    name: gamma22
    bitdepth: 32f
    from_reference: !<ExponentTransform> {value: [2.2, 2.2, 2.2, 1], direction: inverse}
)";
    DisplaySettings s;
    s.config = path.string();
    DisplayTransform display;
    std::string error;
    ASSERT_TRUE(display.init(s, error)) << error;
    EXPECT_EQ(display.describe(), "Monitor / Gamma (" + path.string() + ")");
    EXPECT_EQ(display.outputColorSpace(), "gamma22");
    ImageBuf img = row({0.5f, 0.25f, 1.0f});
    ASSERT_TRUE(display.toDisplay(img));
    EXPECT_NEAR(px(img, 0)[0], std::pow(0.5, 1.0 / 2.2), 1e-5);
    EXPECT_NEAR(px(img, 0)[1], std::pow(0.25, 1.0 / 2.2), 1e-5);
    // The same through $OCIO.
    setenv("OCIO", path.string().c_str(), 1);
    DisplayTransform fromEnv;
    ASSERT_TRUE(fromEnv.init({}, error)) << error;
    EXPECT_NE(fromEnv.describe().find("$OCIO"), std::string::npos);
    unsetenv("OCIO");
    // An OCIO v2 config, with a view transform and a display colour space.
    const auto v2 = std::filesystem::temp_directory_path() / "dhdr_test_v2.ocio";
    std::ofstream(v2) << R"(ocio_profile_version: 2
roles:
  scene_linear: linear
  default: linear
file_rules:
  - !<Rule> {name: Default, colorspace: default}
displays:
  Screen:
    - !<View> {name: Gamma, view_transform: untouched, display_colorspace: gamma24}
view_transforms:
  - !<ViewTransform>
    name: untouched
    from_scene_reference: !<MatrixTransform> {}
display_colorspaces:
  - !<ColorSpace>
    name: gamma24
    from_display_reference: !<ExponentTransform> {value: [2.4, 2.4, 2.4, 1], direction: inverse}
colorspaces:
  - !<ColorSpace>
    name: linear
)";
    s.config = v2.string();
    DisplayTransform fromV2;
    ASSERT_TRUE(fromV2.init(s, error)) << error;
    EXPECT_EQ(fromV2.describe(), "Screen / Gamma (" + v2.string() + ")");
    EXPECT_EQ(fromV2.outputColorSpace(), "gamma24");
    ImageBuf grey = row({0.5f, 0.5f, 0.5f});
    ASSERT_TRUE(fromV2.toDisplay(grey));
    EXPECT_NEAR(px(grey, 0)[0], std::pow(0.5, 1.0 / 2.4), 1e-5);
    // A missing config is an error naming it.
    s.config = "/nonexistent/config.ocio";
    EXPECT_FALSE(display.init(s, error));
    EXPECT_NE(error.find("/nonexistent/config.ocio"), std::string::npos);
}

// A file tagged sRGB (PNG, JPEG) is decoded by the sRGB curve into scene-linear; an untagged
// one, or one tagged linear, is left as it is.
TEST_F(NoOcioEnv, SrgbTaggedInputIsDecodedByTheSrgbCurve) {
    DisplayTransform display;
    std::string error;
    ASSERT_TRUE(display.init({}, error)) << error;
    const std::vector<float> e = {0.0f, 0.02f, 0.04045f, 0.2f, 0.5f, 0.735357f, 1.0f};
    std::vector<float> rgb;
    for (float x : e)
        rgb.insert(rgb.end(), {x, x, x});
    ImageBuf tagged = row(rgb), linear = row(rgb);
    tagged.specmod().attribute("oiio:ColorSpace", "sRGB");
    linear.specmod().attribute("oiio:ColorSpace", "Linear");
    EXPECT_EQ(display.inputColorSpace(tagged.spec()), kBuiltinSrgbTexture);
    EXPECT_EQ(display.inputColorSpace(linear.spec()), "");
    ASSERT_TRUE(display.toSceneLinear(tagged));
    ASSERT_TRUE(display.toSceneLinear(linear));
    for (size_t i = 0; i < e.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(px(tagged, int(i))[c], srgbDecode(e[i]), 2e-4 * (1.0 + srgbDecode(e[i])))
                << e[i];
            EXPECT_EQ(px(linear, int(i))[c], e[i]);
        }
    // --colorspace given: the file's tag does not override it.
    DisplaySettings explicitInput;
    explicitInput.colorspace = kBuiltinSceneLinear;
    DisplayTransform forced;
    ASSERT_TRUE(forced.init(explicitInput, error)) << error;
    EXPECT_EQ(forced.inputColorSpace(tagged.spec()), "");
}
