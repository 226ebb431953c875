// KHR_materials_sheen (issue 44): the Charlie lobe's albedo table against Monte Carlo in
// double, the layering under uniform light, and the extension read from glTF files written
// here, through dhdr-gbuffer's channels and dhdr-light's pixels, against values computed in
// double from the files' own numbers.
#include "animation_writer.h"
#include "scene_writer.h"
#include "tool_test.h"

#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/lights/light.h>
#include <dhdr/deferred/scene/scene.h>
#include <glm/glm.hpp>
#include <random>

using namespace dhdr;
using namespace dhdr::test;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// The sheen lobe with colour 1 as KHR_materials_sheen writes it, in double: Charlie's
// D = (2 + 1/α) sin(θh)^(1/α) / (2π), α = r², times 1 / (4 (N·L + N·V − N·L N·V)).
double sheenLobe(const glm::dvec3& L, const glm::dvec3& V, double r) {
    const glm::dvec3 H = glm::normalize(L + V);
    const double a = r * r, sin2 = std::max(0.0, 1.0 - H.z * H.z);
    const double D = (2.0 + 1.0 / a) * std::pow(sin2, 0.5 / a) / (2.0 * kPiD);
    return D / (4.0 * (L.z + V.z - L.z * V.z));
}

struct Estimate {
    double mean, sigma;
};

// E(μ) = ∫ f cos θl dω by Monte Carlo: l uniform over the hemisphere (pdf 1 / 2π), n samples
// from a fixed seed; its standard error with it.
Estimate sheenAlbedoMc(double mu, double r, int n = 1 << 21) {
    std::mt19937_64 rng(0x5eedu + std::uint64_t(mu * 1000.0) * 977u + std::uint64_t(r * 1000.0));
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const glm::dvec3 V(std::sqrt(1.0 - mu * mu), 0.0, mu);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const double z = u(rng), phi = 2.0 * kPiD * u(rng), s = std::sqrt(1.0 - z * z);
        const double v =
            sheenLobe({s * std::cos(phi), s * std::sin(phi), z}, V, r) * z * 2.0 * kPiD;
        sum += v;
        sum2 += v * v;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

// The table (core/sheen_albedo.cpp) between its entries as well as on them, within 4 standard
// errors plus 1 % of the albedo plus 5·10⁻⁴ (the quadrature's and the bilinear interpolation's
// error, largest where a smooth sheen's albedo falls steeply: 1.8·10⁻⁴ at μ 0.9, r 0.25).
TEST(Sheen, AlbedoTableMatchesMonteCarlo) {
    for (const double r : {0.25, 0.45, 0.7, 1.0})
        for (const double mu : {0.1, 0.3, 0.55, 0.9}) {
            const Estimate e = sheenAlbedoMc(mu, r);
            const double table = sheenAlbedo(float(mu), float(r));
            std::printf("E_sheen(mu %.2f, r %.2f): table %.5f, Monte Carlo %.5f +- %.5f\n", mu, r,
                        table, e.mean, e.sigma);
            EXPECT_NEAR(table, e.mean, 4.0 * e.sigma + 0.01 * e.mean + 5e-4) << mu << " " << r;
            EXPECT_GT(table, 0.0);
            EXPECT_LT(table, 1.0);
        }
}

// The BRDF as brdf.h evaluates it: a bare base, the sheen lobe, and the base scaled by
// 1 − max(sheenColor) E(N·V) (KHR_materials_sheen's albedo scaling), each against the
// formulas in double at one pair of directions.
TEST(Sheen, BrdfLayersTheLobeOverTheBase) {
    PbrSurface s;
    s.baseColor = glm::vec3(0.5f);
    s.roughness = 0.5f;
    s.sheen = {glm::vec3(0.8f, 0.4f, 0.2f), 0.6f};
    const glm::vec3 N(0.0f, 0.0f, 1.0f);
    const glm::vec3 V = glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f));
    const glm::vec3 L = glm::normalize(glm::vec3(-0.3f, 0.5f, 0.7f));
    const glm::vec3 base = evaluateBrdf(s.bare(), N, V, L);
    const double lobe = sheenLobe(glm::dvec3(L), glm::dvec3(V), 0.6);
    const double scale = 1.0 - 0.8 * sheenAlbedoMc(0.8, 0.6).mean;
    const glm::vec3 f = evaluateBrdf(s, N, V, L);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(f[c], base[c] * scale + s.sheen.color[c] * lobe, 2e-3 * f[c]) << c;
    // No sheen: the base unchanged, to the bit.
    PbrSurface none = s;
    none.sheen.color = glm::vec3(0.0f);
    EXPECT_EQ(evaluateBrdf(none, N, V, L), base);
}

// Under uniform light of radiance 1 the layered surface reflects base albedo × (1 − c E) + c E
// for a grey sheen c (ambient light, exactly). With a white Lambert base (no specular layer)
// and a white sheen that is 1: the albedo scaling keeps energy where the sheen adds it.
TEST(Sheen, UniformLightReflectsTheLayeredAlbedo) {
    Light ambient;
    ambient.type = LightType::Ambient;
    ambient.color = glm::vec3(1.0f);
    ambient.intensity = 1.0f;
    PbrSurface s;
    s.dielectricF0 = glm::vec3(0.0f);
    s.dielectricF90 = 0.0f;
    const glm::vec3 N(0.0f, 0.0f, 1.0f);
    for (const float base : {0.25f, 1.0f})
        for (const float mu : {0.2f, 0.7f}) {
            s.baseColor = glm::vec3(base);
            s.sheen = {glm::vec3(1.0f), 0.5f};
            const glm::vec3 V(std::sqrt(1.0f - mu * mu), 0.0f, mu);
            const double E = sheenAlbedoMc(mu, 0.5).mean;
            const glm::vec3 Lo = shadeLight(ambient, s, glm::vec3(0.0f), N, V);
            EXPECT_NEAR(Lo.g, base * (1.0 - E) + E, 0.01 * E + 1e-4) << base << " " << mu;
        }
}

// The files: a 2 × 2 square seen head-on, its material's KHR_materials_sheen as given.
class SheenFiles : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    static nlohmann::json sheened(const nlohmann::json& sheen, const nlohmann::json& pbr) {
        nlohmann::json doc = gltfWithMesh(squareMesh(1.0f));
        const size_t uv = addFloatAccessor(doc, {0, 1, 1, 1, 1, 0, 0, 0}, "VEC2", 4);
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv;
        doc["nodes"] = {{{"name", "square"}, {"mesh", 0}}};
        doc["scenes"] = {{{"nodes", {0}}}};
        doc["materials"][0]["name"] = "cloth";
        doc["materials"][0]["pbrMetallicRoughness"] = pbr;
        // specularFactor 0: no base lobe, so that the base is Lambert's c / π alone.
        doc["materials"][0]["extensions"] = {{"KHR_materials_sheen", sheen},
                                             {"KHR_materials_specular", {{"specularFactor", 0.0}}}};
        doc["extensionsUsed"] = {"KHR_materials_sheen", "KHR_materials_specular"};
        return doc;
    }

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
};

const nlohmann::json kWhiteBase = {{"baseColorFactor", {0.5, 0.5, 0.5, 1}},
                                   {"metallicFactor", 0.0}};

// The factors read back (loadScene and --info), and the channels: factor × texture (colour
// sRGB-decoded RGB, roughness A), in flat and deep G-buffers alike; none without a sheen.
TEST_F(SheenFiles, ChannelsAreFactorsTimesTextures) {
    ImageBuf png(ImageSpec(1, 1, 4, TypeDesc::UINT8));
    png.specmod().attribute("oiio:UnassociatedAlpha", 1);
    const std::uint8_t texel[4] = {255, 128, 64, 102};
    std::memcpy(png.pixeladdr(0, 0), texel, 4);
    ASSERT_TRUE(png.write(path("sheen.png")));
    nlohmann::json doc = sheened({{"sheenColorFactor", {0.9, 0.6, 0.3}},
                                  {"sheenColorTexture", {{"index", 0}}},
                                  {"sheenRoughnessFactor", 0.75},
                                  {"sheenRoughnessTexture", {{"index", 0}}}},
                                 kWhiteBase);
    doc["images"] = {{{"uri", "sheen.png"}}};
    doc["textures"] = {{{"source", 0}}};
    writeJson(path("read.gltf"), doc);
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(path("read.gltf"), scene, error)) << error;
    const Material* m = nullptr;
    for (const Material& x : scene.materials)
        if (x.name == "cloth") m = &x;
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->sheenColor, glm::vec3(0.9f, 0.6f, 0.3f));
    EXPECT_EQ(m->sheenRoughness, 0.75f);
    EXPECT_GE(m->sheenColorTexture.texture, 0);
    EXPECT_GE(m->sheenRoughnessTexture.texture, 0);
    const Result info = run("dhdr-gbuffer " + path("read.gltf") + " --info");
    EXPECT_NE(info.out.find("sheen (0.9, 0.6, 0.3) (roughness 0.75)"), std::string::npos)
        << info.out;
    EXPECT_EQ(info.err.find("not read"), std::string::npos) << info.err;

    const ImageBuf g = gbuffer("sheen_channels", doc);
    EXPECT_EQ(m_err.find("not read"), std::string::npos) << m_err;
    const double rgb[3] = {0.9 * 1.0, 0.6 * std::pow((128 / 255.0 + 0.055) / 1.055, 2.4),
                           0.3 * std::pow((64 / 255.0 + 0.055) / 1.055, 2.4)};
    EXPECT_NEAR(channel(g, 32, 32, "sheen.R"), rgb[0], 2e-3);
    EXPECT_NEAR(channel(g, 32, 32, "sheen.G"), rgb[1], 2e-3);
    EXPECT_NEAR(channel(g, 32, 32, "sheen.B"), rgb[2], 2e-3);
    EXPECT_NEAR(channel(g, 32, 32, "sheenRoughness"), 0.75 * 102 / 255.0, 2e-3);
    // A deep G-buffer carries them too (its values reach dhdr-light: DirectLightFollows…).
    gbuffer("sheen_channels_deep", doc, "--deep");
    const auto in = OIIO::ImageInput::open(path("sheen_channels_deep.exr"));
    ASSERT_TRUE(in);
    EXPECT_TRUE(in->spec().deep);
    for (const char* name : {"sheen.R", "sheen.G", "sheen.B", "sheenRoughness"})
        EXPECT_GE(in->spec().channelindex(name), 0) << name;
    const ImageBuf plain =
        gbuffer("sheen_none", sheened({{"sheenColorFactor", {0, 0, 0}}}, kWhiteBase));
    EXPECT_LT(plain.spec().channelindex("sheen.R"), 0);
    EXPECT_LT(plain.spec().channelindex("sheenRoughness"), 0);
}

// A sheen over a Lambert base lit by a directional light of illuminance π from 45°:
// Lo = (c_base / π · (1 − max(c) E(N·V)) + c · D V) π N·L, E by Monte Carlo here, from a flat
// and a deep G-buffer.
TEST_F(SheenFiles, DirectLightFollowsTheExtension) {
    const nlohmann::json doc = sheened(
        {{"sheenColorFactor", {1.0, 0.5, 0.25}}, {"sheenRoughnessFactor", 0.5}}, kWhiteBase);
    const ImageBuf g = gbuffer("sheen_lit", doc);
    gbuffer("sheen_deep", doc, "--deep");
    std::ofstream(path("sun.json"))
        << R"({"lights": [{"type": "directional", "direction": [-0.70710678, 0, -0.70710678], "intensity": 3.14159265358979}]})";
    for (const std::string in : {"sheen_lit", "sheen_deep"}) {
        const Result r = run("dhdr-light " + path(in + ".exr") + " --lights " + path("sun.json") +
                             " -o " + path(in + "_out.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
    }
    const ImageBuf lit = read("sheen_lit_out.exr"), deep = read("sheen_deep_out.exr");
    for (const int x : {20, 32, 46}) {
        const glm::dvec3 P(channel(g, x, 32, "P.X"), channel(g, x, 32, "P.Y"),
                           channel(g, x, 32, "P.Z"));
        const glm::dvec3 V = glm::normalize(glm::dvec3(0, 0, 3) - P);
        const glm::dvec3 L = glm::normalize(glm::dvec3(1, 0, 1));
        const double r = channel(g, x, 32, "sheenRoughness");
        const double E = sheenAlbedoMc(V.z, r).mean, lobe = sheenLobe(L, V, r);
        const double colour[3] = {1.0, 0.5, 0.25};
        for (int c = 0; c < 3; ++c) {
            const double expected = (0.5 / kPiD * (1.0 - E) + colour[c] * lobe) * kPiD * L.z;
            EXPECT_NEAR(static_cast<const float*>(lit.pixeladdr(x, 32))[c], expected,
                        5e-3 * expected)
                << x << " " << c;
            EXPECT_NEAR(static_cast<const float*>(deep.pixeladdr(x, 32))[c], expected,
                        5e-3 * expected)
                << x << " " << c << " deep";
        }
    }
}

// Hostile sheen fields: factors past the schema's [0, 1] are clamped, a string or a negative
// colour is no sheen, and an extension that is no object or names a texture that does not
// exist is an error naming the file (exit 1, no output), never a crash.
TEST_F(SheenFiles, HostileFieldsAreClampedOrRefused) {
    const ImageBuf big = gbuffer(
        "sheen_big",
        sheened({{"sheenColorFactor", {1e30, 2, 0.5}}, {"sheenRoughnessFactor", 7}}, kWhiteBase));
    EXPECT_EQ(channel(big, 32, 32, "sheen.R"), 1.0f);
    EXPECT_EQ(channel(big, 32, 32, "sheen.G"), 1.0f);
    EXPECT_EQ(channel(big, 32, 32, "sheen.B"), 0.5f);
    EXPECT_EQ(channel(big, 32, 32, "sheenRoughness"), 1.0f);
    const ImageBuf negative =
        gbuffer("sheen_neg", sheened({{"sheenColorFactor", {-1, -1, -1}}}, kWhiteBase));
    EXPECT_LT(negative.spec().channelindex("sheen.R"), 0);
    const ImageBuf text = gbuffer("sheen_str", sheened({{"sheenColorFactor", "abc"}}, kWhiteBase));
    EXPECT_LT(text.spec().channelindex("sheen.R"), 0);
    for (const auto& [name, sheen] : std::vector<std::pair<std::string, nlohmann::json>>{
             {"sheen_notobj", 5},
             {"sheen_badtex",
              {{"sheenColorFactor", {1, 1, 1}}, {"sheenColorTexture", {{"index", 99}}}}}}) {
        writeJson(path(name + ".gltf"), sheened(sheen, kWhiteBase));
        const Result r = run("dhdr-gbuffer " + path(name + ".gltf") + " -o " + path(name + ".exr") +
                             " --lookat 0,0,3,0,0,0 --size 16x16");
        EXPECT_EQ(r.status, 1) << name << r.err;
        EXPECT_NE(r.err.find(name + ".gltf"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(path(name + ".exr"))) << name;
    }
}

} // namespace
