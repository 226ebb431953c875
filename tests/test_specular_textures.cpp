// KHR_materials_specular's textures and KHR_materials_pbrSpecularGlossiness's
// specularGlossinessTexture (issue 44), through dhdr-gbuffer on glTF files written here: the
// G-buffer's specular.RGB, specularWeight, albedo and roughness at known pixels against the
// extensions' formulas evaluated in double on the texels this file wrote (the bytes themselves,
// sRGB-decoded here), and the hostile references, each a warning naming the file and material.
#include "animation_writer.h"
#include "scene_writer.h"
#include "tool_test.h"

#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <dhdr/deferred/scene/scene.h>
#include <filesystem>
#include <fstream>
#include <glm/glm.hpp>
#include <iterator>

using namespace dhdr::test;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

constexpr int kRepeat = 10497, kMirror = 33648, kNearest = 9728;

double srgbDecode(double v) {
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

// 0-255 codes of a texel: RGBA.
using Texel = std::array<int, 4>;

class SpecularTextures : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    // An 8-bit RGBA PNG of `texels.size()` × 1 texels, straight alpha, as written.
    static void writePng(const std::string& name, const std::vector<Texel>& texels) {
        ImageBuf img(ImageSpec(int(texels.size()), 1, 4, TypeDesc::UINT8));
        img.specmod().attribute("oiio:UnassociatedAlpha", 1);
        for (size_t x = 0; x < texels.size(); ++x)
            for (int c = 0; c < 4; ++c)
                static_cast<std::uint8_t*>(img.pixeladdr(int(x), 0))[c] =
                    std::uint8_t(texels[x][size_t(c)]);
        ASSERT_TRUE(img.write(path(name)));
    }

    std::vector<std::uint8_t> bytesOf(const std::string& name) {
        std::ifstream in(path(name), std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }

    // The 2 × 2 square at z = 0 seen head-on: TEXCOORD_0 u from 0 to 1 along +X (v 0 at the
    // top), TEXCOORD_1 the mirror image (1 − u); material 0 "shiny", dielectric, roughness 0.5.
    static nlohmann::json square() {
        nlohmann::json doc = gltfWithMesh(squareMesh(1.0f));
        const size_t uv0 = addFloatAccessor(doc, {0, 1, 1, 1, 1, 0, 0, 0}, "VEC2", 4);
        const size_t uv1 = addFloatAccessor(doc, {1, 1, 0, 1, 0, 0, 1, 0}, "VEC2", 4);
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv0;
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = uv1;
        doc["nodes"] = {{{"name", "square"}, {"mesh", 0}}};
        doc["scenes"] = {{{"nodes", {0}}}};
        doc["materials"][0]["name"] = "shiny";
        doc["materials"][0]["pbrMetallicRoughness"] = {{"baseColorFactor", {0.5, 0.5, 0.5, 1}},
                                                       {"metallicFactor", 0.0},
                                                       {"roughnessFactor", 0.5}};
        return doc;
    }

    // `doc` with KHR_materials_specular `ext` on its material.
    static nlohmann::json specular(nlohmann::json doc, const nlohmann::json& ext) {
        doc["materials"][0]["extensions"]["KHR_materials_specular"] = ext;
        doc["extensionsUsed"] = {"KHR_materials_specular"};
        return doc;
    }

    // dhdr-gbuffer of `doc` (written as `name`.gltf, or given as a file) seen head-on.
    ImageBuf gbuffer(const std::string& name, const nlohmann::json& doc,
                     const std::string& extra = "") {
        writeJson(path(name + ".gltf"), doc);
        return render(name + ".gltf", name, extra);
    }
    ImageBuf render(const std::string& file, const std::string& name,
                    const std::string& extra = "") {
        const Result r =
            run("dhdr-gbuffer " + path(file) + " --lookat 0,0,3,0,0,0 --fov 60 --size 64x64 " +
                extra + " -o " + path(name + ".exr"));
        EXPECT_EQ(r.status, 0) << r.err;
        m_err = r.err;
        return read(name + ".exr");
    }

    // The pixels of row 32 on the square, each with its u; none within a tenth of a texel of a
    // texel's edge on a 4-texel row for any of the coordinates `edges` maps u to.
    template <class Edges>
    static std::vector<std::pair<int, double>> pixels(const ImageBuf& g, Edges edges) {
        std::vector<std::pair<int, double>> out;
        for (int x = 0; x < 64; ++x) {
            if (channel(g, x, 32, "A") != 1.0f) continue;
            const double u = (double(channel(g, x, 32, "P.X")) + 1.0) / 2.0;
            bool edge = false;
            for (const double t : edges(u))
                edge = edge || std::abs(t * 4.0 - std::round(t * 4.0)) < 0.1;
            if (!edge) out.emplace_back(x, u);
        }
        return out;
    }

    std::string m_err;
};

// 4-texel rows; texel i of a 4 × 1 NEAREST texture at coordinate t (REPEAT).
int texelAt(double t) {
    return ((int(std::floor(t * 4.0)) % 4) + 4) % 4;
}

const std::vector<Texel> kStrength = {
    {10, 20, 30, 255}, {10, 20, 30, 191}, {10, 20, 30, 128}, {10, 20, 30, 32}};
const std::vector<Texel> kColor = {
    {255, 128, 64, 255}, {64, 255, 128, 255}, {128, 64, 255, 255}, {200, 200, 200, 255}};

// dielectric_f0 = min(((ior − 1)/(ior + 1))² · specularColorFactor · specularColorTexture.rgb, 1)
// · specularFactor · specularTexture.a, dielectric_f90 = specularFactor · specularTexture.a (the
// README's "Implementation"), per texel: specularTexture with KHR_texture_transform scale 2 on
// TEXCOORD_0, specularColorTexture on TEXCOORD_1 (u mirrored) with its own sampler. A colour
// factor of 40 makes 0.04 × 40 = 1.6 × the texel: the min clamps the brightest texels.
TEST_F(SpecularTextures, TexturesScaleTheFactorsPerTexel) {
    writePng("strength.png", kStrength);
    writePng("colour.png", kColor);
    nlohmann::json doc = square();
    doc["images"] = {{{"uri", "strength.png"}}, {{"uri", "colour.png"}}};
    doc["samplers"] = {{{"magFilter", kNearest}, {"wrapS", kRepeat}}};
    doc["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 1}, {"sampler", 0}}};
    const double factor = 0.8, colour[3] = {40.0, 10.0, 5.0};
    doc = specular(doc, {{"specularFactor", factor},
                         {"specularColorFactor", {colour[0], colour[1], colour[2]}},
                         {"specularTexture",
                          {{"index", 0},
                           {"extensions", {{"KHR_texture_transform", {{"scale", {2.0, 1.0}}}}}}}},
                         {"specularColorTexture", {{"index", 1}, {"texCoord", 1}}}});
    doc["extensionsUsed"].push_back("KHR_texture_transform");
    const ImageBuf g = gbuffer("spec_tex", doc);
    EXPECT_EQ(m_err.find("not read"), std::string::npos) << m_err;
    EXPECT_EQ(m_err.find("magenta"), std::string::npos) << m_err;
    const auto px = pixels(g, [](double u) { return std::vector<double>{2.0 * u, 1.0 - u}; });
    ASSERT_GT(px.size(), 20u);
    int clamped = 0;
    for (const auto& [x, u] : px) {
        const Texel& s = kStrength[size_t(texelAt(2.0 * u))];
        const Texel& c = kColor[size_t(texelAt(1.0 - u))];
        const double weight = factor * s[3] / 255.0;
        const char* names[3] = {"specular.R", "specular.G", "specular.B"};
        for (int k = 0; k < 3; ++k) {
            const double f0 = 0.04 * colour[k] * srgbDecode(c[size_t(k)] / 255.0);
            clamped += f0 > 1.0;
            const double expected = std::min(f0, 1.0) * weight;
            // half: 2⁻¹¹ relative
            EXPECT_NEAR(channel(g, x, 32, names[k]), expected, 1e-3 * expected + 1e-5)
                << "x " << x << " u " << u << " " << names[k];
        }
        EXPECT_NEAR(channel(g, x, 32, "specularWeight"), weight, 1e-3 * weight + 1e-5) << x;
        // The base is untouched.
        EXPECT_EQ(channel(g, x, 32, "albedo.R"), 0.5f) << x;
    }
    EXPECT_GT(clamped, 0);

    // --info and the loader list them in their slots.
    const Result info = run("dhdr-gbuffer " + path("spec_tex.gltf") + " --info");
    EXPECT_NE(info.out.find("specular strength.png, specular colour colour.png"), std::string::npos)
        << info.out;
    EXPECT_EQ(info.out.find("(not read)"), std::string::npos) << info.out;
    dhdr::Scene scene;
    std::string error;
    ASSERT_TRUE(dhdr::loadScene(path("spec_tex.gltf"), scene, error)) << error;
    const dhdr::Material& m = scene.materials[0];
    EXPECT_EQ(m.specularTexture.texCoord, 0);
    EXPECT_EQ(m.specularTexture.transform.scale, glm::vec2(2.0f, 1.0f));
    EXPECT_EQ(m.specularColorTexture.texCoord, 1);
    EXPECT_TRUE(m.specularColorTexture.sampler.nearest);
}

// The sampler of a texture only the JSON names: MIRRORED_REPEAT on u from −1 to 2 (OpenGL's
// period-8 mirror of the texel index), against specularWeight.
TEST_F(SpecularTextures, SamplerWrapModesApply) {
    writePng("strength_w.png", kStrength);
    nlohmann::json doc = square();
    doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] =
        addFloatAccessor(doc, {-1, 1, 2, 1, 2, 0, -1, 0}, "VEC2", 4);
    doc["images"] = {{{"uri", "strength_w.png"}}};
    doc["samplers"] = {{{"magFilter", kNearest}, {"wrapS", kMirror}, {"wrapT", kRepeat}}};
    doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    doc = specular(doc, {{"specularTexture", {{"index", 0}}}});
    const ImageBuf g = gbuffer("spec_mirror", doc);
    const auto px = pixels(g, [](double u) { return std::vector<double>{3.0 * u - 1.0}; });
    ASSERT_GT(px.size(), 20u);
    for (const auto& [x, u] : px) {
        int i = ((int(std::floor((3.0 * u - 1.0) * 4.0)) % 8) + 8) % 8;
        if (i >= 4) i = 7 - i;
        // half: 2⁻¹¹ relative
        EXPECT_NEAR(channel(g, x, 32, "specularWeight"), kStrength[size_t(i)][3] / 255.0, 5e-4)
            << "u " << 3.0 * u - 1.0;
    }
}

// Images the file holds itself, which Assimp 5.2 never sees for these slots: a bufferView of a
// .gltf (the same image as the base colour's, which Assimp reads: both paths give the same
// texels), a data URI, and a .glb's BIN chunk.
TEST_F(SpecularTextures, EmbeddedImagesAreDecodedFromTheFile) {
    writePng("colour_e.png", kColor);
    const std::vector<std::uint8_t> png = bytesOf("colour_e.png");
    nlohmann::json doc = square();
    doc["buffers"].push_back({{"byteLength", png.size()},
                              {"uri", "data:application/octet-stream;base64," + base64(png)}});
    doc["bufferViews"].push_back(
        {{"buffer", doc["buffers"].size() - 1}, {"byteLength", png.size()}});
    doc["images"] = {{{"bufferView", doc["bufferViews"].size() - 1}, {"mimeType", "image/png"}},
                     {{"uri", "data:image/png;base64," + base64(png)}}};
    doc["samplers"] = {{{"magFilter", kNearest}}};
    doc["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 1}, {"sampler", 0}}};
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1, 1};
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    const double colour = 20.0; // F0 = 0.8 × the texel: no clamping
    for (const int index : {0, 1}) {
        const std::string name = "spec_embedded" + std::to_string(index);
        const ImageBuf g =
            gbuffer(name, specular(doc, {{"specularColorFactor", {colour, colour, colour}},
                                         {"specularColorTexture", {{"index", index}}}}));
        EXPECT_EQ(m_err.find("magenta"), std::string::npos) << m_err;
        const auto px = pixels(g, [](double u) { return std::vector<double>{u}; });
        ASSERT_GT(px.size(), 20u);
        for (const auto& [x, u] : px) {
            const Texel& c = kColor[size_t(texelAt(u))];
            const char* spec[3] = {"specular.R", "specular.G", "specular.B"};
            const char* albedo[3] = {"albedo.R", "albedo.G", "albedo.B"};
            for (int k = 0; k < 3; ++k) {
                const double texel = srgbDecode(c[size_t(k)] / 255.0);
                EXPECT_NEAR(channel(g, x, 32, spec[k]), 0.04 * colour * texel, 1e-3 * texel)
                    << name << " x " << x;
                // Assimp's decoding of the same image (base colour) and this one agree.
                EXPECT_NEAR(channel(g, x, 32, spec[k]) / (0.04f * float(colour)),
                            channel(g, x, 32, albedo[k]), 1e-3 * texel)
                    << name << " x " << x;
            }
        }
    }

    // Where Assimp decoded the same bytes (the base colour's "*0": the same image, or another
    // holding the same PNG), that is the one texture.
    for (const char* file : {"spec_embedded0.gltf", "spec_embedded1.gltf"}) {
        dhdr::Scene scene;
        std::string error;
        ASSERT_TRUE(dhdr::loadScene(path(file), scene, error)) << error;
        EXPECT_EQ(scene.materials[0].specularColorTexture.texture,
                  scene.materials[0].baseColorTexture.texture)
            << file;
        EXPECT_EQ(scene.textures.size(), 1u) << file;
    }

    // A .glb whose buffer 0 is its BIN chunk, holding the image only.
    nlohmann::json glb = specular(doc, {{"specularColorFactor", {colour, colour, colour}},
                                        {"specularColorTexture", {{"index", 0}}}});
    glb["materials"][0]["pbrMetallicRoughness"].erase("baseColorTexture");
    for (auto& view : glb["bufferViews"])
        view["buffer"] = view["buffer"].get<size_t>() + 1;
    glb["buffers"].insert(glb["buffers"].begin(),
                          nlohmann::json::object({{"byteLength", png.size()}}));
    glb["bufferViews"].push_back({{"buffer", 0}, {"byteLength", png.size()}});
    glb["images"] = {{{"bufferView", glb["bufferViews"].size() - 1}, {"mimeType", "image/png"}}};
    std::string json = glb.dump();
    json.resize((json.size() + 3) / 4 * 4, ' ');
    std::vector<std::uint8_t> bin = png;
    bin.resize((bin.size() + 3) / 4 * 4, 0);
    auto u32 = [](std::string& out, std::uint32_t v) {
        out.append(reinterpret_cast<char*>(&v), 4);
    };
    std::string file = "glTF";
    u32(file, 2);
    u32(file, std::uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    u32(file, std::uint32_t(json.size()));
    file += "JSON" + json;
    u32(file, std::uint32_t(bin.size()));
    file += std::string("BIN\0", 4) + std::string(bin.begin(), bin.end());
    std::ofstream(path("spec.glb"), std::ios::binary) << file;
    const ImageBuf g = render("spec.glb", "spec_glb");
    EXPECT_EQ(m_err.find("magenta"), std::string::npos) << m_err;
    dhdr::Scene scene;
    std::string error;
    ASSERT_TRUE(dhdr::loadScene(path("spec.glb"), scene, error)) << error;
    EXPECT_EQ(scene.textures[size_t(scene.materials[0].specularColorTexture.texture)].name,
              "images[0]");
    const auto px = pixels(g, [](double u) { return std::vector<double>{u}; });
    ASSERT_GT(px.size(), 20u);
    for (const auto& [x, u] : px) {
        const double texel = srgbDecode(kColor[size_t(texelAt(u))][1] / 255.0);
        EXPECT_NEAR(channel(g, x, 32, "specular.G"), 0.04 * colour * texel, 1e-3 * texel) << x;
    }
}

// A texture seen from far (256 texels across ~37 pixels) is filtered over each pixel's footprint
// as every slot is: a checkerboard of alpha 0 and 1 averages to 1/2 (linear alpha), where one
// lookup per pixel would give 0 or 1.
TEST_F(SpecularTextures, MinifiedTexturesAreFilteredOverTheFootprint) {
    ImageBuf img(ImageSpec(256, 256, 4, TypeDesc::UINT8));
    img.specmod().attribute("oiio:UnassociatedAlpha", 1);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            auto* p = static_cast<std::uint8_t*>(img.pixeladdr(x, y));
            p[0] = p[1] = p[2] = 255;
            p[3] = (x + y) % 2 ? 255 : 0;
        }
    ASSERT_TRUE(img.write(path("checker.png")));
    nlohmann::json doc = square();
    doc["images"] = {{{"uri", "checker.png"}}};
    doc["textures"] = {{{"source", 0}}};
    const ImageBuf g =
        gbuffer("spec_checker", specular(doc, {{"specularTexture", {{"index", 0}}}}));
    for (const int x : {20, 32, 44})
        for (const int y : {20, 32, 44})
            EXPECT_NEAR(channel(g, x, y, "specularWeight"), 0.5, 0.02) << x << " " << y;
}

// KHR_materials_pbrSpecularGlossiness's README, "Specular - Glossiness", per texel:
// diffuse = diffuseFactor × diffuseTexture, specular = specularFactor × the texture's RGB (sRGB),
// glossiness = glossinessFactor × its A (linear); c_diff = diffuse × (1 − max(specular)),
// F0 = specular, α = (1 − glossiness)² (roughness 1 − glossiness), metallic 0, F90 1.
TEST_F(SpecularTextures, SpecularGlossinessTextureConvertsPerTexel) {
    const std::vector<Texel> diffuse = {
        {255, 255, 255, 255}, {200, 150, 100, 255}, {128, 128, 128, 255}, {50, 100, 200, 255}};
    const std::vector<Texel> sg = {
        {64, 64, 64, 255}, {200, 100, 50, 128}, {128, 200, 255, 0}, {30, 30, 30, 200}};
    writePng("sg_diffuse.png", diffuse);
    writePng("sg.png", sg);
    nlohmann::json doc = square();
    doc["images"] = {{{"uri", "sg_diffuse.png"}}, {{"uri", "sg.png"}}};
    doc["samplers"] = {{{"magFilter", kNearest}}};
    doc["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 1}, {"sampler", 0}}};
    const double df[3] = {0.9, 0.8, 0.7}, sf[3] = {0.6, 0.8, 1.0}, gf = 0.9;
    doc["materials"][0]["extensions"] = {{"KHR_materials_pbrSpecularGlossiness",
                                          {{"diffuseFactor", {df[0], df[1], df[2], 1.0}},
                                           {"specularFactor", {sf[0], sf[1], sf[2]}},
                                           {"glossinessFactor", gf},
                                           {"diffuseTexture", {{"index", 0}}},
                                           {"specularGlossinessTexture", {{"index", 1}}}}}};
    doc["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness"};
    const ImageBuf g = gbuffer("sg_tex", doc);
    EXPECT_EQ(m_err.find("not read"), std::string::npos) << m_err;
    EXPECT_EQ(m_err.find("magenta"), std::string::npos) << m_err;
    const auto px = pixels(g, [](double u) { return std::vector<double>{u}; });
    ASSERT_GT(px.size(), 20u);
    for (const auto& [x, u] : px) {
        const size_t i = size_t(texelAt(u));
        double spec[3], largest = 0.0;
        for (int k = 0; k < 3; ++k) {
            spec[k] = sf[k] * srgbDecode(sg[i][size_t(k)] / 255.0);
            largest = std::max(largest, spec[k]);
        }
        const double roughness = 1.0 - gf * sg[i][3] / 255.0;
        const char* rgb[3] = {"R", "G", "B"};
        for (int k = 0; k < 3; ++k) {
            const double albedo = df[k] * srgbDecode(diffuse[i][size_t(k)] / 255.0) * (1 - largest);
            EXPECT_NEAR(channel(g, x, 32, (std::string("albedo.") + rgb[k]).c_str()), albedo,
                        1e-3 * albedo + 1e-5)
                << "x " << x << " texel " << i;
            EXPECT_NEAR(channel(g, x, 32, (std::string("specular.") + rgb[k]).c_str()), spec[k],
                        1e-3 * spec[k] + 1e-5)
                << "x " << x << " texel " << i;
        }
        EXPECT_NEAR(channel(g, x, 32, "roughness"), roughness, 1e-3 * roughness + 1e-5) << x;
        EXPECT_EQ(channel(g, x, 32, "metallic"), 0.0f);
        EXPECT_EQ(channel(g, x, 32, "specularWeight"), 1.0f);
    }
    const Result info = run("dhdr-gbuffer " + path("sg_tex.gltf") + " --info");
    EXPECT_NE(info.out.find("specular-glossiness sg.png"), std::string::npos) << info.out;
    EXPECT_NE(info.out.find("specular-glossiness per texel: specular (0.6, 0.8, 1), glossiness "
                            "0.9"),
              std::string::npos)
        << info.out;
}

// References that lead nowhere: each a warning naming the file, the material and the slot (the
// texture magenta, as any unread one), never a crash; an error with --strict. A texCoord past
// TEXCOORD_1 is sampled with TEXCOORD_0, warned naming the material.
TEST_F(SpecularTextures, HostileReferencesAreWarnedNamingFileAndMaterial) {
    writePng("strength_h.png", kStrength);
    std::ofstream(path("broken.png")) << "not a png";
    nlohmann::json base = square();
    base["images"] = {{{"uri", "strength_h.png"}}, {{"uri", "nothere.png"}},
                      {{"uri", "broken.png"}},     {{"uri", "data:image/png;base64,AAAA"}},
                      {{"bufferView", 42}},        {{"uri", 7}}};
    base["samplers"] = {{{"wrapS", 12345}}};
    base["textures"] = {{{"source", 0}, {"sampler", 9}},
                        {{"source", 1}},
                        {{"source", 2}},
                        {{"source", 3}},
                        {{"source", 4}},
                        {{"source", 99}},
                        {{"sampler", 0}},
                        {{"source", 5}},
                        {{"source", 0}, {"sampler", 0}}};
    const std::vector<std::pair<std::string, nlohmann::json>> cases = {
        {"index_past_textures", {{"index", 99}}},
        {"index_negative", {{"index", -1}}},
        {"no_object", 0},
        {"missing_file", {{"index", 1}}},
        {"broken_file", {{"index", 2}}},
        {"bad_data_uri", {{"index", 3}}},
        {"bufferview_past", {{"index", 4}}},
        {"source_past_images", {{"index", 5}}},
        {"no_source", {{"index", 6}}},
        {"uri_not_string", {{"index", 7}}}};
    for (const auto& [name, ref] : cases) {
        for (const char* slot : {"specularTexture", "specularColorTexture"}) {
            const std::string file = "hostile_" + name + "_" + slot;
            writeJson(path(file + ".gltf"), specular(base, {{slot, ref}}));
            const Result r = run("dhdr-gbuffer " + path(file + ".gltf") + " -o " +
                                 path(file + ".exr") + " --lookat 0,0,3,0,0,0 --size 16x16");
            EXPECT_EQ(r.status, 0) << file << ": " << r.err;
            EXPECT_NE(r.err.find(file + ".gltf: material 'shiny', specular"), std::string::npos)
                << file << ": " << r.err;
            EXPECT_TRUE(std::filesystem::exists(path(file + ".exr"))) << file;
        }
    }
    // A sampler past the list, or with an unknown wrap value: REPEAT, no message.
    writeJson(path("hostile_sampler.gltf"),
              specular(base, {{"specularTexture", {{"index", 0}}},
                              {"specularColorTexture", {{"index", 8}}}}));
    Result r = run("dhdr-gbuffer " + path("hostile_sampler.gltf") + " -o " +
                   path("hostile_sampler.exr") + " --lookat 0,0,3,0,0,0 --size 16x16");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;

    // --strict: an error naming the file, no output.
    writeJson(path("hostile_strict.gltf"), specular(base, {{"specularTexture", {{"index", 99}}}}));
    r = run("dhdr-gbuffer " + path("hostile_strict.gltf") + " --strict -o " +
            path("hostile_strict.exr") + " --lookat 0,0,3,0,0,0 --size 16x16");
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("hostile_strict.gltf"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("texture 99 does not exist"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(path("hostile_strict.exr")));

    // texCoord 7 (and one in the transform's override): TEXCOORD_0, the material named.
    for (const auto& ref :
         {nlohmann::json{{"index", 0}, {"texCoord", 7}},
          nlohmann::json{{"index", 0},
                         {"extensions", {{"KHR_texture_transform", {{"texCoord", 7}}}}}}}) {
        writeJson(path("hostile_uv7.gltf"), specular(base, {{"specularColorTexture", ref}}));
        r = run("dhdr-gbuffer " + path("hostile_uv7.gltf") + " -o " + path("hostile_uv7.exr") +
                " --lookat 0,0,3,0,0,0 --size 16x16");
        EXPECT_EQ(r.status, 0) << r.err;
        EXPECT_NE(r.err.find("hostile_uv7.gltf: textures on UV sets past TEXCOORD_1 are sampled "
                             "with TEXCOORD_0 (material 'shiny')"),
                  std::string::npos)
            << r.err;
    }

    // specularGlossinessTexture, read from the JSON as the extension's factors are: a missing
    // image or an index past the textures is the same warning. With the extension in
    // extensionsUsed, Assimp 5.2 reads the reference too, and refuses an index past the textures:
    // an error naming the file, no output.
    nlohmann::json sg = base;
    sg["materials"][0]["extensions"] = {
        {"KHR_materials_pbrSpecularGlossiness", {{"specularGlossinessTexture", {{"index", 1}}}}}};
    for (const int index : {1, 99}) {
        sg["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"]
          ["specularGlossinessTexture"]["index"] = index;
        const std::string file = "hostile_sg" + std::to_string(index);
        writeJson(path(file + ".gltf"), sg);
        r = run("dhdr-gbuffer " + path(file + ".gltf") + " -o " + path(file + ".exr") +
                " --lookat 0,0,3,0,0,0 --size 16x16");
        EXPECT_EQ(r.status, 0) << r.err;
        EXPECT_NE(r.err.find(file + ".gltf: material 'shiny', specular-glossiness texture"),
                  std::string::npos)
            << r.err;
    }
    sg["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness"};
    writeJson(path("hostile_sg_used.gltf"), sg);
    r = run("dhdr-gbuffer " + path("hostile_sg_used.gltf") + " -o " + path("hostile_sg_used.exr") +
            " --lookat 0,0,3,0,0,0 --size 16x16");
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("hostile_sg_used.gltf"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(path("hostile_sg_used.exr")));
}

} // namespace
