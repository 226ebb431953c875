// The glTF 2.0 material model as dhdr-gbuffer reads it (issue 44): samplers' wrap modes and
// filters, the second UV set, metallic-roughness, occlusion and vertex colours, straight
// alpha, normal maps seen from behind their slope. Each through the tools, on files written
// here, against values computed from the files' own numbers.
#include "animation_writer.h"
#include "scene_writer.h"
#include "tool_test.h"

#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <cstring>
#include <dhdr/deferred/scene/scene.h>
#include <glm/glm.hpp>

using namespace dhdr::test;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

constexpr int kRepeat = 10497, kClamp = 33071, kMirror = 33648, kNearest = 9728;

double srgbDecode(double v) {
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

class Materials : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    // An 8-bit PNG of `width` × 1 texels (RGB, or RGBA with `alpha`) from 0-255 values.
    static void writePng(const std::string& name, const std::vector<std::array<int, 4>>& texels,
                         bool alpha = false) {
        const int nch = alpha ? 4 : 3;
        ImageBuf img(ImageSpec(int(texels.size()), 1, nch, TypeDesc::UINT8));
        // The values are the file's: straight, not to be un-premultiplied on the way out.
        img.specmod().attribute("oiio:UnassociatedAlpha", 1);
        for (size_t x = 0; x < texels.size(); ++x)
            for (int c = 0; c < nch; ++c)
                static_cast<std::uint8_t*>(img.pixeladdr(int(x), 0))[c] =
                    std::uint8_t(texels[x][size_t(c)]);
        ASSERT_TRUE(img.write(path(name)));
    }

    // The 2 × 2 square at z = 0 with TEXCOORD_0 running from u0 to u1 along +X (v from 0 at
    // the top to 1 at the bottom), seen from the front.
    static nlohmann::json square(float u0 = 0.0f, float u1 = 1.0f) {
        nlohmann::json doc = gltfWithMesh(squareMesh(1.0f));
        // Vertices (−1,−1), (1,−1), (1,1), (−1,1).
        const size_t uv = addFloatAccessor(doc, {u0, 1, u1, 1, u1, 0, u0, 0}, "VEC2", 4);
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv;
        doc["nodes"] = {{{"name", "square"}, {"mesh", 0}}};
        doc["scenes"] = {{{"nodes", {0}}}};
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1, 1};
        return doc;
    }

    // dhdr-gbuffer of `doc` seen head-on; the G-buffer read back.
    ImageBuf gbuffer(const std::string& name, const nlohmann::json& doc,
                     const std::string& extra = "") {
        writeJson(path(name + ".gltf"), doc);
        const Result r = run("dhdr-gbuffer " + path(name + ".gltf") +
                             " --lookat 0,0,3,0,0,0 --fov 60 --size 64x64 " + extra + " -o " +
                             path(name + ".exr"));
        EXPECT_EQ(r.status, 0) << r.err;
        m_err = r.err;
        return read(name + ".exr");
    }

    std::string m_err;

public:
    static nlohmann::json squareDoc() { return square(); }
};

// KHR_materials_clearcoat: a square coated with `coat` over `base` (glTF material JSON).
nlohmann::json coated(const nlohmann::json& coat, const nlohmann::json& pbr) {
    nlohmann::json doc = Materials::squareDoc();
    doc["materials"][0]["pbrMetallicRoughness"] = pbr;
    doc["materials"][0]["extensions"] = {{"KHR_materials_clearcoat", coat},
                                         {"KHR_materials_specular", {{"specularFactor", 0.0}}}};
    doc["extensionsUsed"] = {"KHR_materials_clearcoat", "KHR_materials_specular"};
    return doc;
}

// Each wrap mode against OpenGL's rule for the texel index i of u on a 4-texel row (NEAREST,
// so that every pixel is one texel): REPEAT i mod 4, MIRRORED_REPEAT the period-8 mirror,
// CLAMP_TO_EDGE clamped to [0, 3]; the square's u runs from −1 to 2.
TEST_F(Materials, WrapModesFollowTheSampler) {
    const std::vector<std::array<int, 4>> texels = {
        {255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 0, 255}};
    writePng("row.png", texels);
    for (const int wrap : {kRepeat, kMirror, kClamp}) {
        nlohmann::json doc = square(-1.0f, 2.0f);
        doc["images"] = {{{"uri", "row.png"}}};
        doc["samplers"] = {{{"wrapS", wrap}, {"wrapT", kRepeat}, {"magFilter", kNearest}}};
        doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
        const ImageBuf g = gbuffer("wrap" + std::to_string(wrap), doc);
        int checked = 0;
        for (int x = 0; x < 64; ++x) {
            if (channel(g, x, 32, "A") != 1.0f) continue;
            const double u = (double(channel(g, x, 32, "P.X")) + 1.0) / 2.0 * 3.0 - 1.0;
            const double t = u * 4.0;
            if (std::abs(t - std::round(t)) < 0.1) continue; // a texel's edge
            const int i = int(std::floor(t));
            int expected = wrap == kRepeat  ? ((i % 4) + 4) % 4
                           : wrap == kClamp ? std::clamp(i, 0, 3)
                                            : ((i % 8) + 8) % 8;
            if (wrap == kMirror && expected >= 4) expected = 7 - expected;
            const auto& e = texels[size_t(expected)];
            EXPECT_EQ(channel(g, x, 32, "albedo.R"), e[0] / 255.0f) << wrap << " u " << u;
            EXPECT_EQ(channel(g, x, 32, "albedo.G"), e[1] / 255.0f) << wrap << " u " << u;
            EXPECT_EQ(channel(g, x, 32, "albedo.B"), e[2] / 255.0f) << wrap << " u " << u;
            ++checked;
        }
        EXPECT_GE(checked, 30) << wrap;
    }
}

// A texture on TEXCOORD_1, named by the reference or by KHR_texture_transform's texCoord: its
// halves follow the second set (u along +X) while the first set is constant.
TEST_F(Materials, SecondUvSetIsSampled) {
    writePng("halves.png", {{255, 0, 0, 255}, {0, 0, 255, 255}});
    for (const bool override : {false, true}) {
        nlohmann::json doc = square(0.3f, 0.3f); // TEXCOORD_0: one point of the red half
        const size_t uv1 = addFloatAccessor(doc, {0, 1, 1, 1, 1, 0, 0, 0}, "VEC2", 4);
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = uv1;
        doc["images"] = {{{"uri", "halves.png"}}};
        doc["samplers"] = {{{"magFilter", kNearest}}};
        doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
        nlohmann::json ref = {{"index", 0}, {"texCoord", 1}};
        if (override) {
            ref = {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}};
            doc["extensionsUsed"] = {"KHR_texture_transform"};
        }
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = ref;
        const ImageBuf g = gbuffer(override ? "uv1o" : "uv1", doc);
        EXPECT_EQ(m_err.find("UV set"), std::string::npos) << m_err;
        // A quarter of the square in from each side.
        EXPECT_EQ(channel(g, 21, 32, "albedo.R"), 1.0f) << override;
        EXPECT_EQ(channel(g, 42, 32, "albedo.B"), 1.0f) << override;
        EXPECT_EQ(channel(g, 42, 32, "albedo.R"), 0.0f) << override;
    }
}

// roughness = roughnessFactor × G, metallic = metallicFactor × B of the linear texture.
TEST_F(Materials, MetallicRoughnessTextureScalesTheFactors) {
    writePng("mr.png", {{200, 128, 255, 255}});
    nlohmann::json doc = square();
    doc["images"] = {{{"uri", "mr.png"}}};
    doc["textures"] = {{{"source", 0}}};
    auto& pbr = doc["materials"][0]["pbrMetallicRoughness"];
    pbr["metallicRoughnessTexture"] = {{"index", 0}};
    pbr["roughnessFactor"] = 0.8;
    pbr["metallicFactor"] = 0.6;
    const ImageBuf g = gbuffer("mr", doc);
    // Stored as half: within half's rounding (2⁻¹¹ relative).
    EXPECT_NEAR(channel(g, 32, 32, "roughness"), 0.8 * 128.0 / 255.0, 1e-3);
    EXPECT_NEAR(channel(g, 32, 32, "metallic"), 0.6, 1e-3);
    EXPECT_LT(g.spec().channelindex("occlusion"), 0); // no occlusion texture, no channel
}

// The occlusion channel: 1 + strength · (R − 1), written only for a scene that uses it; in
// dhdr-light it scales an ambient light's contribution and leaves a directional light's.
TEST_F(Materials, OcclusionScalesAmbientButNotDirectLight) {
    writePng("ao.png", {{64, 255, 255, 255}});
    nlohmann::json doc = square();
    doc["images"] = {{{"uri", "ao.png"}}};
    doc["textures"] = {{{"source", 0}}};
    doc["materials"][0]["occlusionTexture"] = {{"index", 0}, {"strength", 0.5}};
    const ImageBuf g = gbuffer("ao", doc);
    const double occlusion = 1.0 + 0.5 * (64.0 / 255.0 - 1.0);
    ASSERT_NEAR(channel(g, 32, 32, "occlusion"), occlusion, 1e-3);
    // The same G-buffer without the channel: what a reader without occlusion sees.
    std::vector<int> keep;
    std::vector<std::string> names;
    for (int c = 0; c < g.nchannels(); ++c)
        if (g.spec().channelnames[size_t(c)] != "occlusion") {
            keep.push_back(c);
            names.push_back(g.spec().channelnames[size_t(c)]);
        }
    ImageBuf without = OIIO::ImageBufAlgo::channels(g, int(keep.size()), keep, {}, names);
    without.specmod().channelformats.clear();
    ASSERT_TRUE(without.write(path("ao_without.exr"), TypeDesc::FLOAT));
    std::ofstream(path("ambient.json"))
        << R"({"lights": [{"type": "ambient", "color": [1, 1, 1], "intensity": 0.5}]})";
    std::ofstream(path("sun.json"))
        << R"({"lights": [{"type": "directional", "direction": [0, 0, -1], "intensity": 2}]})";
    for (const char* lights : {"ambient", "sun"}) {
        for (const char* in : {"ao", "ao_without"}) {
            const Result r = run("dhdr-light " + path(std::string(in) + ".exr") + " --lights " +
                                 path(std::string(lights) + ".json") + " -o " +
                                 path(std::string(in) + "_" + lights + ".exr"));
            ASSERT_EQ(r.status, 0) << r.err;
        }
        const ImageBuf with = read(std::string("ao_") + lights + ".exr"),
                       plain = read(std::string("ao_without_") + lights + ".exr");
        const float a = static_cast<const float*>(with.pixeladdr(32, 32))[0];
        const float b = static_cast<const float*>(plain.pixeladdr(32, 32))[0];
        ASSERT_GT(b, 0.0f) << lights;
        const double expected = std::string(lights) == "ambient" ? occlusion : 1.0;
        EXPECT_NEAR(a / b, expected, 2e-3) << lights;
    }
}

// COLOR_0 multiplies the base colour: RGB floats (whose alpha Assimp 5.2 reads as 0, dhdr
// as 1: the MASK material stays), and RGBA whose alpha cuts a MASK material out.
TEST_F(Materials, VertexColoursMultiplyBaseColourAndAlpha) {
    for (const bool rgba : {false, true}) {
        nlohmann::json doc = square();
        std::vector<float> colors;
        for (int v = 0; v < 4; ++v)
            for (const float c : {0.5f, 0.25f, 1.0f, 0.2f})
                if (rgba || c != 0.2f) colors.push_back(c);
        doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
            addFloatAccessor(doc, colors, rgba ? "VEC4" : "VEC3", 4);
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {0.8, 0.8, 0.8, 1.0};
        doc["materials"][0]["alphaMode"] = "MASK";
        const ImageBuf g = gbuffer(rgba ? "colors4" : "colors3", doc);
        if (rgba) {
            EXPECT_EQ(channel(g, 32, 32, "A"), 0.0f); // alpha 0.2 < the cutoff 0.5
            continue;
        }
        ASSERT_EQ(channel(g, 32, 32, "A"), 1.0f);
        EXPECT_NEAR(channel(g, 32, 32, "albedo.R"), 0.8 * 0.5, 1e-3);
        EXPECT_NEAR(channel(g, 32, 32, "albedo.G"), 0.8 * 0.25, 1e-3);
        EXPECT_NEAR(channel(g, 32, 32, "albedo.B"), 0.8 * 1.0, 1e-3);
    }
}

// A half-transparent texel's colour is its own, decoded from sRGB, not premultiplied by its
// alpha before the decode (OpenImageIO associates a PNG's alpha unless told not to).
TEST_F(Materials, TextureColourIsStraightNotPremultiplied) {
    writePng("half.png", {{128, 128, 128, 128}}, true);
    // The texel as libpng holds it, read back by OpenImageIO without associating its alpha.
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    ImageBuf check(path("half.png"), 0, 0, nullptr, &config);
    ASSERT_TRUE(check.read(0, 0, true, TypeDesc::UINT8));
    ASSERT_EQ(static_cast<const std::uint8_t*>(check.pixeladdr(0, 0))[0], 128);
    nlohmann::json doc = square();
    doc["images"] = {{{"uri", "half.png"}}};
    doc["textures"] = {{{"source", 0}}};
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    doc["materials"][0]["alphaMode"] = "BLEND";
    const ImageBuf g = gbuffer("straight", doc, "--flat");
    EXPECT_NEAR(channel(g, 32, 32, "albedo.R"), srgbDecode(128.0 / 255.0), 1e-3) << m_err;
}

// A normal map tilted towards +u, seen from the −X side where the mapped normal faces away:
// the normal is bent to just in front of the viewer, keeping its tilt (N.X > 0), not turned
// round to −mapped.
TEST_F(Materials, MappedNormalFacingAwayIsBentNotTurned) {
    writePng("tilt.png", {{255, 128, 153, 255}}); // (x, y, z) ≈ (1, 0, 0.2)
    nlohmann::json doc = square();
    doc["images"] = {{{"uri", "tilt.png"}}};
    doc["textures"] = {{{"source", 0}}};
    doc["materials"][0]["normalTexture"] = {{"index", 0}};
    writeJson(path("tilt.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("tilt.gltf") +
                         " --lookat -3,0,1,0,0,0 --fov 40 --size 32x32 -o " + path("tilt.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf g = read("tilt.exr");
    int checked = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            if (channel(g, x, y, "A") != 1.0f) continue;
            const glm::vec3 P(channel(g, x, y, "P.X"), channel(g, x, y, "P.Y"),
                              channel(g, x, y, "P.Z"));
            const glm::vec3 N(channel(g, x, y, "N.X"), channel(g, x, y, "N.Y"),
                              channel(g, x, y, "N.Z"));
            const glm::vec3 V = glm::normalize(glm::vec3(-3, 0, 1) - P);
            EXPECT_GT(N.x, 0.0f) << x << "," << y;
            EXPECT_GE(glm::dot(N, V), -2e-3f) << x << "," << y; // half's rounding
            ++checked;
        }
    EXPECT_GT(checked, 50);
}

// A texture on a UV set dhdr does not read is named; the render goes on with TEXCOORD_0.
TEST_F(Materials, UvSetsPastTheSecondAreNamed) {
    writePng("one.png", {{255, 0, 0, 255}});
    nlohmann::json doc = square();
    doc["images"] = {{{"uri", "one.png"}}};
    doc["textures"] = {{{"source", 0}}};
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0},
                                                                       {"texCoord", 7}};
    const ImageBuf g = gbuffer("uv7", doc);
    EXPECT_NE(m_err.find("past TEXCOORD_1"), std::string::npos) << m_err;
    EXPECT_EQ(channel(g, 32, 32, "albedo.R"), 1.0f);
}

// The coat's channels: its factors × textures (R weight, G roughness), and its normal, the
// interpolated one (no clearcoat normal map); none of them in a G-buffer without a coat.
TEST_F(Materials, ClearcoatChannelsAreFactorsTimesTextures) {
    writePng("coat.png", {{128, 64, 255, 255}});
    nlohmann::json doc = coated({{"clearcoatFactor", 0.8},
                                 {"clearcoatTexture", {{"index", 0}}},
                                 {"clearcoatRoughnessFactor", 0.5},
                                 {"clearcoatRoughnessTexture", {{"index", 0}}}},
                                {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0.0}});
    doc["images"] = {{{"uri", "coat.png"}}};
    doc["textures"] = {{{"source", 0}}};
    const ImageBuf g = gbuffer("coat_channels", doc);
    EXPECT_EQ(m_err.find("not read"), std::string::npos) << m_err;
    EXPECT_NEAR(channel(g, 32, 32, "clearcoat"), 0.8 * 128.0 / 255.0, 1e-3);
    EXPECT_NEAR(channel(g, 32, 32, "clearcoatRoughness"), 0.5 * 64.0 / 255.0, 1e-3);
    for (const char* axis : {"X", "Y", "Z"})
        EXPECT_EQ(channel(g, 32, 32, (std::string("clearcoatN.") + axis).c_str()),
                  channel(g, 32, 32, (std::string("N.") + axis).c_str()))
            << axis;
    const ImageBuf plain = gbuffer("coat_plain", square());
    EXPECT_LT(plain.spec().channelindex("clearcoat"), 0);
    EXPECT_LT(plain.spec().channelindex("clearcoatN.X"), 0);
}

// A coat over a Lambert base (specularFactor 0: no base lobe), lit by a directional light of
// illuminance π from 45°: KHR_materials_clearcoat's mix(material, clearcoat_brdf, b),
// b = clearcoat (0.04 + 0.96 (1 − V·Nc)⁵), clearcoat_brdf = D G / (4 |V·Nc| |L·Nc|), computed
// here in double from the G-buffer's own point and roughness. The same from a deep G-buffer,
// whose reader once dropped every channel written only when used.
TEST_F(Materials, ClearcoatLayersItsLobeOverTheBase) {
    const nlohmann::json doc =
        coated({{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.3}},
               {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0.0}});
    const ImageBuf g = gbuffer("coat_lit", doc);
    gbuffer("coat_deep", doc, "--deep");
    std::ofstream(path("coat_sun.json"))
        << R"({"lights": [{"type": "directional", "direction": [-0.70710678, 0, -0.70710678], "intensity": 3.14159265358979}]})";
    for (const std::string in : {"coat_lit", "coat_deep"}) {
        const Result r = run("dhdr-light " + path(in + ".exr") + " --lights " +
                             path("coat_sun.json") + " -o " + path(in + "_out.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
    }
    const ImageBuf lit = read("coat_lit_out.exr");
    const ImageBuf deep = read("coat_deep_out.exr"); // dhdr-light's frame of the deep samples
    for (const int x : {32, 46}) {
        const glm::dvec3 P(channel(g, x, 32, "P.X"), channel(g, x, 32, "P.Y"),
                           channel(g, x, 32, "P.Z"));
        const glm::dvec3 V = glm::normalize(glm::dvec3(0, 0, 3) - P), N(0, 0, 1);
        const glm::dvec3 L = glm::normalize(glm::dvec3(1, 0, 1));
        const glm::dvec3 H = glm::normalize(L + V);
        const double a = std::pow(double(channel(g, x, 32, "clearcoatRoughness")), 2.0);
        const double a2 = a * a, nh = glm::dot(N, H), nl = glm::dot(N, L), nv = glm::dot(N, V);
        const double D = a2 / (M_PI * std::pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));
        const double vis = 0.5 / (nl * std::sqrt(nv * nv * (1.0 - a2) + a2) +
                                  nv * std::sqrt(nl * nl * (1.0 - a2) + a2));
        const double b = 0.04 + 0.96 * std::pow(1.0 - nv, 5.0);
        const double expected = ((1.0 - b) * 0.5 / M_PI + b * D * vis) * M_PI * nl;
        const float* p = static_cast<const float*>(lit.pixeladdr(x, 32));
        EXPECT_NEAR(p[0], expected, 2e-3 * expected) << x;
        EXPECT_NEAR(p[2], expected, 2e-3 * expected) << x;
        EXPECT_NEAR(static_cast<const float*>(deep.pixeladdr(x, 32))[0], expected, 2e-3 * expected)
            << x << " deep";
    }
}

// Hostile clearcoat fields: factors past the schema's [0, 1] are clamped, a string is no
// coat, and an extension that is no object or names a texture that does not exist is an
// error naming the file (exit 1, no output), never a crash.
TEST_F(Materials, HostileClearcoatFieldsAreClampedOrRefused) {
    const nlohmann::json white = {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0.0}};
    const ImageBuf big = gbuffer(
        "coat_big", coated({{"clearcoatFactor", 1e30}, {"clearcoatRoughnessFactor", 7}}, white));
    EXPECT_EQ(channel(big, 32, 32, "clearcoat"), 1.0f);
    EXPECT_EQ(channel(big, 32, 32, "clearcoatRoughness"), 1.0f);
    const ImageBuf negative = gbuffer(
        "coat_neg", coated({{"clearcoatFactor", -1}, {"clearcoatRoughnessFactor", -5}}, white));
    EXPECT_LT(negative.spec().channelindex("clearcoat"), 0);
    const ImageBuf text = gbuffer("coat_str", coated({{"clearcoatFactor", "abc"}}, white));
    EXPECT_LT(text.spec().channelindex("clearcoat"), 0);
    for (const auto& [name, coat] : std::vector<std::pair<std::string, nlohmann::json>>{
             {"coat_notobj", 5},
             {"coat_badtex", {{"clearcoatFactor", 1}, {"clearcoatTexture", {{"index", 99}}}}}}) {
        writeJson(path(name + ".gltf"), coated(coat, white));
        const Result r = run("dhdr-gbuffer " + path(name + ".gltf") + " -o " + path(name + ".exr") +
                             " --lookat 0,0,3,0,0,0 --size 16x16");
        EXPECT_EQ(r.status, 1) << name << r.err;
        EXPECT_NE(r.err.find(name + ".gltf"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(path(name + ".exr"))) << name;
    }
}

// Under a uniform ambient light of radiance 1 the coat's lobe reflects all it receives
// (its multiple scattering kept): Lo = (1 − b) · albedo + b.
TEST_F(Materials, ClearcoatUnderUniformLightKeepsItsEnergy) {
    const ImageBuf g = gbuffer(
        "coat_amb", coated({{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.6}},
                           {{"baseColorFactor", {0.25, 0.25, 0.25, 1}}, {"metallicFactor", 0.0}}));
    std::ofstream(path("coat_ambient.json"))
        << R"({"lights": [{"type": "ambient", "color": [1, 1, 1], "intensity": 1}]})";
    const Result r = run("dhdr-light " + path("coat_amb.exr") + " --lights " +
                         path("coat_ambient.json") + " -o " + path("coat_amb_out.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf lit = read("coat_amb_out.exr");
    for (const int x : {20, 46}) {
        const glm::dvec3 P(channel(g, x, 32, "P.X"), channel(g, x, 32, "P.Y"),
                           channel(g, x, 32, "P.Z"));
        const double nv = glm::normalize(glm::dvec3(0, 0, 3) - P).z;
        const double b = 0.04 + 0.96 * std::pow(1.0 - nv, 5.0);
        const double expected = (1.0 - b) * 0.25 + b;
        EXPECT_NEAR(static_cast<const float*>(lit.pixeladdr(x, 32))[1], expected, 3e-3) << x;
    }
}

} // namespace

namespace {

// KHR_materials_ior and KHR_materials_specular: the G-buffer's dielectric reflectance is
// min(((ior − 1)/(ior + 1))² · specularColorFactor, 1) · specularFactor at normal incidence and
// specularFactor at grazing incidence; a scene without them has no such channels.
TEST_F(Materials, IorAndSpecularSetTheDielectricReflectance) {
    nlohmann::json doc = square();
    doc["materials"][0]["extensions"] = {
        {"KHR_materials_ior", {{"ior", 2.0}}},
        {"KHR_materials_specular",
         {{"specularFactor", 0.5}, {"specularColorFactor", {1.0, 0.5, 0.25}}}}};
    doc["extensionsUsed"] = {"KHR_materials_ior", "KHR_materials_specular"};
    const ImageBuf g = gbuffer("ior", doc);
    EXPECT_EQ(m_err.find("not read"), std::string::npos) << m_err;
    const double f0 = 1.0 / 9.0 * 0.5;
    EXPECT_NEAR(channel(g, 32, 32, "specular.R"), f0 * 1.0, 1e-4);
    EXPECT_NEAR(channel(g, 32, 32, "specular.G"), f0 * 0.5, 1e-4);
    EXPECT_NEAR(channel(g, 32, 32, "specular.B"), f0 * 0.25, 1e-4);
    EXPECT_EQ(channel(g, 32, 32, "specularWeight"), 0.5f);
    const ImageBuf plain = gbuffer("plain", square());
    EXPECT_LT(plain.spec().channelindex("specular.R"), 0);
    EXPECT_LT(plain.spec().channelindex("specularWeight"), 0);
}

// specularFactor 0 leaves a dielectric its diffuse layer alone, undimmed by any Fresnel:
// lit head-on by a directional light of illuminance π, Lo = albedo / π · π · cos 0 = albedo.
TEST_F(Materials, SpecularFactorZeroLeavesLambertsLawExactly) {
    nlohmann::json doc = square();
    doc["materials"][0]["pbrMetallicRoughness"] = {{"baseColorFactor", {0.5, 0.25, 0.125, 1.0}},
                                                   {"metallicFactor", 0.0},
                                                   {"roughnessFactor", 0.5}};
    doc["materials"][0]["extensions"] = {{"KHR_materials_specular", {{"specularFactor", 0.0}}}};
    gbuffer("nospec", doc);
    std::ofstream(path("pi.json"))
        << R"({"lights": [{"type": "directional", "direction": [0, 0, -1], "intensity": 3.14159265358979}]})";
    const Result r = run("dhdr-light " + path("nospec.exr") + " --lights " + path("pi.json") +
                         " -o " + path("nospec_lit.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf lit = read("nospec_lit.exr");
    const float* p = static_cast<const float*>(lit.pixeladdr(32, 32));
    // The G-buffer's half albedo and the output's half: 2⁻¹¹ relative each.
    EXPECT_NEAR(p[0], 0.5, 1e-3);
    EXPECT_NEAR(p[1], 0.25, 1e-3);
    EXPECT_NEAR(p[2], 0.125, 1e-3);
}

// KHR_materials_unlit: what the surface shows is its base colour (× vertex colour), whatever
// lights the scene: its emission, with nothing reflected.
TEST_F(Materials, UnlitShowsItsBaseColourUnderAnyLight) {
    nlohmann::json doc = square();
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {0.2, 0.4, 0.6, 1.0};
    doc["materials"][0]["extensions"] = {{"KHR_materials_unlit", nlohmann::json::object()}};
    doc["extensionsUsed"] = {"KHR_materials_unlit"};
    const ImageBuf g = gbuffer("unlit", doc);
    EXPECT_EQ(m_err.find("not read"), std::string::npos) << m_err;
    EXPECT_EQ(channel(g, 32, 32, "albedo.R"), 0.0f);
    std::ofstream(path("bright.json"))
        << R"({"lights": [{"type": "directional", "direction": [0, 0, -1], "intensity": 5},
                          {"type": "ambient", "intensity": 2}]})";
    const Result r = run("dhdr-light " + path("unlit.exr") + " --lights " + path("bright.json") +
                         " -o " + path("unlit_lit.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf lit = read("unlit_lit.exr");
    const float* p = static_cast<const float*>(lit.pixeladdr(32, 32));
    EXPECT_NEAR(p[0], 0.2, 1e-3);
    EXPECT_NEAR(p[1], 0.4, 1e-3);
    EXPECT_NEAR(p[2], 0.6, 1e-3);
}

} // namespace

// KHR_materials_pbrSpecularGlossiness as its README's BRDF: c_diff = diffuse · (1 − max(specular)),
// F0 = specular, α = (1 − glossiness)², i.e. metallic 0, roughness 1 − glossiness, F90 1; the
// metal-rough fallback (red, metallic, its texture) is not the material; the diffuse texture
// multiplies the diffuse colour, the specularGlossinessTexture the specular one.
TEST_F(Materials, SpecularGlossinessBecomesItsMetalRoughEquivalent) {
    writePng("sg_diffuse.png", {{255, 128, 64, 255}});
    nlohmann::json doc = square();
    doc["materials"][0]["pbrMetallicRoughness"] = {{"baseColorFactor", {1, 0, 0, 1}},
                                                   {"metallicFactor", 1.0},
                                                   {"baseColorTexture", {{"index", 0}}}};
    doc["materials"][0]["extensions"] = {{"KHR_materials_pbrSpecularGlossiness",
                                          {{"diffuseFactor", {0.5, 0.4, 0.3, 1.0}},
                                           {"specularFactor", {0.2, 0.1, 0.05}},
                                           {"glossinessFactor", 0.75}}}};
    doc["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness"};
    doc["images"] = {{{"uri", "sg_diffuse.png"}}};
    doc["textures"] = {{{"source", 0}}};
    const ImageBuf g = gbuffer("specgloss", doc);
    EXPECT_EQ(m_err.find("not read"), std::string::npos) << m_err;
    const float albedo[3] = {0.5f * 0.8f, 0.4f * 0.8f, 0.3f * 0.8f};
    const float f0[3] = {0.2f, 0.1f, 0.05f};
    const char* rgb[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
        // half channels: 2⁻¹¹ relative
        EXPECT_NEAR(channel(g, 32, 32, (std::string("albedo.") + rgb[c]).c_str()), albedo[c], 1e-3);
        EXPECT_NEAR(channel(g, 32, 32, (std::string("specular.") + rgb[c]).c_str()), f0[c], 1e-3);
    }
    EXPECT_EQ(channel(g, 32, 32, "metallic"), 0.0f);
    EXPECT_EQ(channel(g, 32, 32, "roughness"), 0.25f);
    EXPECT_EQ(channel(g, 32, 32, "specularWeight"), 1.0f);

    // The diffuse texture (sRGB) multiplies the diffuse colour.
    doc["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"]["diffuseTexture"] = {
        {"index", 0}};
    const ImageBuf t = gbuffer("specgloss_tex", doc);
    const double texel[3] = {1.0, srgbDecode(128.0 / 255.0), srgbDecode(64.0 / 255.0)};
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(channel(t, 32, 32, (std::string("albedo.") + rgb[c]).c_str()),
                    albedo[c] * texel[c], 2e-3)
            << c;

    // The specularGlossinessTexture (sRGB RGB) scales the specular colour, F0, and dims the
    // diffuse by 1 − its largest component (SpecularTextures.* test it texel by texel).
    doc["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"]
       ["specularGlossinessTexture"] = {{"index", 0}};
    const ImageBuf sg = gbuffer("specgloss_sgtex", doc);
    EXPECT_EQ(m_err.find("not read"), std::string::npos) << m_err;
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(channel(sg, 32, 32, (std::string("specular.") + rgb[c]).c_str()),
                    f0[c] * texel[c], 1e-3)
            << c;
    EXPECT_NEAR(channel(sg, 32, 32, "albedo.R"), 0.5 * texel[0] * (1.0 - 0.2), 2e-3);
}
