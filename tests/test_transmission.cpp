// KHR_materials_transmission (issue 44): read from glTF files written here, through
// dhdr-gbuffer's `transmission` channel and dhdr-light's pixels, against values computed from
// the files' own numbers. A thin-walled surface (the extension without KHR_materials_volume)
// passes what lies behind it straight through, tinted by its base colour and dimmed by its
// dielectric's reflection; its diffuse layer keeps 1 − transmission of the light.
#include "animation_writer.h"
#include "scene_writer.h"
#include "tool_test.h"

#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/scene/scene.h>
#include <glm/glm.hpp>

using namespace dhdr;
using namespace dhdr::test;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

// The pane's base colour, distinct per channel so that a tint lost or swapped shows.
constexpr double kTint[3] = {0.9, 0.5, 0.2};

class TransmissionFiles : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    // A 2 × 2 pane at z = 0 of material "glass" (base colour kTint, roughness 0, the extension
    // `transmission` and `extra` extensions) in front of a 8 × 8 wall at z = −1 of material
    // "wall" (black without a specular layer, emitting `wall`), both facing the camera on +Z.
    static nlohmann::json paneBeforeWall(const nlohmann::json& transmission, double wall,
                                         const nlohmann::json& extra = nlohmann::json::object()) {
        nlohmann::json doc = gltfWithMesh(squareMesh(1.0f));
        const size_t uv = addFloatAccessor(doc, {0, 1, 1, 1, 1, 0, 0, 0}, "VEC2", 4);
        nlohmann::json& primitive = doc["meshes"][0]["primitives"][0];
        primitive["attributes"]["TEXCOORD_0"] = uv;
        nlohmann::json wallPrimitive = primitive;
        wallPrimitive["material"] = 1;
        doc["meshes"].push_back({{"name", "wall"}, {"primitives", {wallPrimitive}}});
        doc["nodes"] = {
            {{"name", "pane"}, {"mesh", 0}},
            {{"name", "wall"}, {"mesh", 1}, {"translation", {0, 0, -1}}, {"scale", {4, 4, 1}}}};
        doc["scenes"] = {{{"nodes", {0, 1}}}};
        nlohmann::json extensions = extra;
        extensions["KHR_materials_transmission"] = transmission;
        doc["materials"] = {
            {{"name", "glass"},
             {"pbrMetallicRoughness",
              {{"baseColorFactor", {kTint[0], kTint[1], kTint[2], 1.0}},
               {"metallicFactor", 0.0},
               {"roughnessFactor", 0.0}}},
             {"extensions", extensions}},
            {{"name", "wall"},
             {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
             {"emissiveFactor", {wall, wall, wall}},
             {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}}}};
        nlohmann::json used = {"KHR_materials_specular"};
        for (const auto& [name, value] : extensions.items())
            if (name != "KHR_materials_specular") used.push_back(name);
        doc["extensionsUsed"] = used;
        return doc;
    }

    // The G-buffer of `doc` at 64 × 64 from (0, 0, 3), and the lit frame of it under `lights`
    // (a lights file's JSON; none: the scene's emission alone).
    ImageBuf render(const std::string& name, const nlohmann::json& doc,
                    const std::string& lights = "", const std::string& lightArgs = "") {
        writeJson(path(name + ".gltf"), doc);
        Result r = run("dhdr-gbuffer " + path(name + ".gltf") +
                       " --lookat 0,0,3,0,0,0 --fov 60 --size 64x64 -o " + path(name + ".exr"));
        EXPECT_EQ(r.status, 0) << r.err;
        m_gbufferErr = r.err;
        std::string lightOption = " --scene " + path(name + ".gltf");
        if (!lights.empty()) {
            std::ofstream(path(name + ".lights.json")) << lights;
            lightOption += " --lights " + path(name + ".lights.json");
        }
        r = run("dhdr-light " + path(name + ".exr") + lightOption + " --gi direct " + lightArgs +
                " -o " + path(name + "_lit.exr"));
        EXPECT_EQ(r.status, 0) << r.err;
        return read(name + "_lit.exr");
    }

    static float pixel(const ImageBuf& img, int x, int y, int c) {
        return static_cast<const float*>(img.pixeladdr(x, y))[c];
    }

    std::string m_gbufferErr;
};

// No specular reflection (KHR_materials_specular's factor 0): the wall through the pane is the
// wall's radiance × transmission × base colour, exactly; beside the pane, the wall as it is.
TEST_F(TransmissionFiles, PassesTheWallTintedByTheBaseColour) {
    for (const double T : {1.0, 0.5}) {
        const std::string name = "pane_" + std::to_string(int(T * 10));
        const ImageBuf lit =
            render(name, paneBeforeWall({{"transmissionFactor", T}}, 1.0,
                                        {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}));
        EXPECT_EQ(m_gbufferErr.find("not read"), std::string::npos) << m_gbufferErr;
        const auto in = OIIO::ImageInput::open(path(name + ".exr"));
        ASSERT_TRUE(in);
        EXPECT_TRUE(in->spec().deep) << "a transmissive surface in view makes the G-buffer deep";
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(pixel(lit, 32, 32, c), T * kTint[c], 2e-3 * kTint[c]) << T << " " << c;
            EXPECT_NEAR(pixel(lit, 2, 32, c), 1.0, 1e-3) << c;
        }
        EXPECT_NEAR(pixel(lit, 32, 32, 3), 1.0, 1e-6);
    }
}

// The default dielectric (IOR 1.5): what passes is also dimmed by what the smooth surface
// reflects at the pixel's angle, 1 − F; Schlick's F = 0.04 + 0.96 (1 − cos θ)⁵ with θ the
// angle between the pixel's ray and the pane's normal.
TEST_F(TransmissionFiles, TheDielectricReflectionIsNotPassed) {
    const ImageBuf lit = render("pane_ior", paneBeforeWall({{"transmissionFactor", 1.0}}, 1.0));
    for (const int x : {32, 20}) {
        // Pixel centres at fov 60° over 64 pixels: the ray's direction from the camera.
        const double t = std::tan(30.0 * 3.14159265358979 / 180.0);
        const double dx = ((x + 0.5) / 32.0 - 1.0) * t, dy = (1.0 - 32.5 / 32.0) * t;
        const double cosTheta = 1.0 / std::sqrt(1.0 + dx * dx + dy * dy);
        const double F = 0.04 + 0.96 * std::pow(1.0 - cosTheta, 5.0);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(pixel(lit, x, 32, c), kTint[c] * (1.0 - F), 3e-3 * kTint[c]) << x << c;
    }
}

// Light on the pane: its diffuse layer gets 1 − transmission of it (glTF's
// mix(diffuse_brdf, specular_btdf, transmission)); a black wall adds nothing behind. A sun
// along −Z of intensity π on a Lambert surface facing it reflects the base colour.
TEST_F(TransmissionFiles, TheDiffuseLayerKeepsTheRest) {
    const std::string sun =
        R"({"lights": [{"type": "directional", "direction": [0, 0, -1], "intensity": 3.14159265358979}]})";
    for (const double T : {0.0, 0.25, 1.0}) {
        const ImageBuf lit =
            render("lit_" + std::to_string(int(T * 100)),
                   paneBeforeWall({{"transmissionFactor", T}}, 0.0,
                                  {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}),
                   sun, "--no-shadows");
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(pixel(lit, 32, 32, c), (1.0 - T) * kTint[c], 2e-3 * kTint[c]) << T << c;
    }
}

// transmissionTexture's R scales the factor, per texel (CLAMP_TO_EDGE: the left half 0, the
// right half 1); the G-buffer's `transmission` channel holds the product.
TEST_F(TransmissionFiles, TheTextureScalesTheFactor) {
    ImageBuf png(ImageSpec(4, 1, 3, TypeDesc::UINT8));
    const std::uint8_t texels[12] = {0, 9, 9, 0, 9, 9, 255, 9, 9, 255, 9, 9};
    std::memcpy(png.localpixels(), texels, sizeof texels);
    ASSERT_TRUE(png.write(path("transmission.png")));
    nlohmann::json doc =
        paneBeforeWall({{"transmissionFactor", 0.8}, {"transmissionTexture", {{"index", 0}}}}, 1.0,
                       {{"KHR_materials_specular", {{"specularFactor", 0.0}}}});
    doc["images"] = {{{"uri", "transmission.png"}}};
    doc["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33071}}};
    doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    writeJson(path("read.gltf"), doc);
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(path("read.gltf"), scene, error)) << error;
    const Material* glass = nullptr;
    for (const Material& m : scene.materials)
        if (m.name == "glass") glass = &m;
    ASSERT_NE(glass, nullptr);
    EXPECT_EQ(glass->transmission, 0.8f);
    EXPECT_GE(glass->transmissionTexture.texture, 0);
    const Result info = run("dhdr-gbuffer " + path("read.gltf") + " --info");
    EXPECT_NE(info.out.find("transmission 0.8"), std::string::npos) << info.out;

    const ImageBuf lit = render("textured", doc);
    // --flat keeps each pixel's first surface: the pane's own sample.
    const Result flat =
        run("dhdr-gbuffer " + path("textured.gltf") +
            " --lookat 0,0,3,0,0,0 --fov 60 --size 64x64 --flat -o " + path("textured_flat.exr"));
    ASSERT_EQ(flat.status, 0) << flat.err;
    const ImageBuf g = read("textured_flat.exr");
    const int channel = g.spec().channelindex("transmission");
    ASSERT_GE(channel, 0);
    EXPECT_NEAR(pixel(g, 18, 32, channel), 0.0, 1e-3);
    EXPECT_NEAR(pixel(g, 46, 32, channel), 0.8, 1e-3);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(pixel(lit, 18, 32, c), 0.0, 1e-4) << c;
        EXPECT_NEAR(pixel(lit, 46, 32, c), 0.8 * kTint[c], 2e-3 * kTint[c]) << c;
    }
}

// dhdr-light --deep-out: each lit sample stored so that OpenImageIO's flatten (front-to-back
// "over", a reader that is not dhdr's) gives the frame's colour, tint included.
TEST_F(TransmissionFiles, DeepOutputFlattensToTheFrame) {
    const ImageBuf lit = render("deep_out", paneBeforeWall({{"transmissionFactor", 0.7}}, 1.0), "",
                                "--deep-out " + path("deep_out_samples.exr"));
    ImageBuf deep(path("deep_out_samples.exr"));
    ASSERT_TRUE(deep.read()) << deep.geterror();
    ASSERT_TRUE(deep.deep());
    ImageBuf flat;
    ASSERT_TRUE(OIIO::ImageBufAlgo::flatten(flat, deep)) << flat.geterror();
    for (const int x : {2, 20, 32, 46})
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(flat.getchannel(x, 32, 0, c), pixel(lit, x, 32, c),
                        1e-3 * pixel(lit, x, 32, c) + 1e-5)
                << x << " " << c;
}

// A 2 × 2 × 2 glass cube (KHR_materials_volume: thickness 1, attenuation colour C over
// distance 1, white and without reflection) before the wall: the light crosses 2 of the medium,
// Beer's law gives C², once (the far face does not absorb again); beside it, the wall.
TEST_F(TransmissionFiles, TheVolumeAbsorbsAlongThePathInside) {
    GltfMesh cube;
    // Each face its own four vertices, wound counter-clockwise seen from outside.
    const int faces[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}, {1, 0, 2}, {2, 0, 1}, {2, 1, 0}};
    for (int f = 0; f < 6; ++f) {
        const int n = faces[f][0], u = faces[f][1], v = faces[f][2];
        const float s = f % 2 == 0 ? 1.0f : -1.0f;
        const auto base = std::uint32_t(cube.positions.size());
        for (const auto& [a, b] : {std::pair{-1.f, -1.f}, {1.f, -1.f}, {1.f, 1.f}, {-1.f, 1.f}}) {
            std::array<float, 3> p{}, normal{};
            p[size_t(n)] = s;
            p[size_t(u)] = a;
            p[size_t(v)] = b * s;
            normal[size_t(n)] = s;
            cube.positions.push_back(p);
            cube.normals.push_back(normal);
        }
        for (const std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u})
            cube.indices.push_back(base + k);
    }
    nlohmann::json doc = paneBeforeWall({{"transmissionFactor", 1.0}}, 1.0,
                                        {{"KHR_materials_specular", {{"specularFactor", 0.0}}},
                                         {"KHR_materials_volume",
                                          {{"thicknessFactor", 1.0},
                                           {"attenuationDistance", 1.0},
                                           {"attenuationColor", {0.5, 0.8, 1.0}}}}});
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1, 1};
    // Mesh 0 becomes the cube (its own buffer), the wall moved back to z = -3.
    const nlohmann::json cubeDoc = gltfWithMesh(cube);
    const size_t views = doc["bufferViews"].size(), accessors = doc["accessors"].size();
    const size_t buffer = doc["buffers"].size();
    doc["buffers"].push_back(cubeDoc["buffers"][0]);
    for (nlohmann::json view : cubeDoc["bufferViews"]) {
        view["buffer"] = buffer;
        doc["bufferViews"].push_back(view);
    }
    for (nlohmann::json a : cubeDoc["accessors"]) {
        a["bufferView"] = a["bufferView"].get<size_t>() + views;
        doc["accessors"].push_back(a);
    }
    nlohmann::json primitive = cubeDoc["meshes"][0]["primitives"][0];
    for (auto& [name, index] : primitive["attributes"].items())
        index = index.get<size_t>() + accessors;
    primitive["indices"] = primitive["indices"].get<size_t>() + accessors;
    doc["meshes"][0]["primitives"] = {primitive};
    doc["nodes"][1]["translation"] = {0, 0, -3};
    doc["nodes"][1]["scale"] = {8, 8, 1};
    const ImageBuf lit = render("cube", doc);
    const double C[3] = {0.5, 0.8, 1.0};
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(pixel(lit, 32, 32, c), C[c] * C[c], 3e-3) << c;
        EXPECT_NEAR(pixel(lit, 1, 1, c), 1.0, 1e-3) << c;
    }
    const Result info = run("dhdr-gbuffer " + path("cube.gltf") + " --info");
    EXPECT_NE(info.out.find("volume absorbing to (0.5, 0.8, 1) over 1"), std::string::npos)
        << info.out;
    EXPECT_EQ(info.err.find("not read"), std::string::npos) << info.err;
}

// Hostile extension objects: each file renders (values clamped to the schema's ranges, a
// broken member ignored as Assimp ignores it) or is refused naming the file, and no lit pixel
// is NaN or infinite.
TEST_F(TransmissionFiles, HostileFieldsAreClampedOrRefused) {
    using J = nlohmann::json;
    const std::pair<const char*, J> cases[] = {
        {"factor_string", {{"KHR_materials_transmission", {{"transmissionFactor", "x"}}}}},
        {"factor_big", {{"KHR_materials_transmission", {{"transmissionFactor", 7}}}}},
        {"factor_negative", {{"KHR_materials_transmission", {{"transmissionFactor", -1}}}}},
        {"texture_missing",
         {{"KHR_materials_transmission",
           {{"transmissionFactor", 1}, {"transmissionTexture", {{"index", 99}}}}}}},
        {"not_an_object", {{"KHR_materials_transmission", J::array({1, 2})}}},
        {"volume_distance_negative",
         {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
          {"KHR_materials_volume",
           {{"thicknessFactor", 1},
            {"attenuationDistance", -1},
            {"attenuationColor", {.5, .5, .5}}}}}},
        {"volume_extremes",
         {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
          {"KHR_materials_volume",
           {{"thicknessFactor", 1e30},
            {"attenuationDistance", 1e-30},
            {"attenuationColor", {5, -1, 0}}}}}},
        {"volume_colour_short",
         {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
          {"KHR_materials_volume",
           {{"thicknessFactor", 1}, {"attenuationDistance", 1}, {"attenuationColor", {0.5}}}}}},
    };
    for (const auto& [name, extensions] : cases) {
        nlohmann::json doc = paneBeforeWall({{"transmissionFactor", 0.5}}, 1.0);
        doc["materials"][0]["extensions"] = extensions;
        doc["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_volume"};
        const std::string file = path(std::string(name) + ".gltf");
        writeJson(file, doc);
        const Result g = run("dhdr-gbuffer " + file + " --lookat 0,0,3,0,0,0 --size 32x32 -o " +
                             path(std::string(name) + ".exr"));
        ASSERT_TRUE(g.status == 0 || g.status == 1) << name << ": " << g.err;
        if (g.status == 1) {
            EXPECT_NE(g.err.find(file), std::string::npos) << name << ": " << g.err;
            EXPECT_FALSE(fs::exists(path(std::string(name) + ".exr"))) << name;
            continue;
        }
        const Result l = run("dhdr-light " + path(std::string(name) + ".exr") + " --scene " + file +
                             " --gi direct -o " + path(std::string(name) + "_lit.exr"));
        ASSERT_EQ(l.status, 0) << name << ": " << l.err;
        const ImageBuf lit = read(std::string(name) + "_lit.exr");
        const auto stats = OIIO::ImageBufAlgo::computePixelStats(lit);
        for (int c = 0; c < 4; ++c) {
            EXPECT_EQ(stats.nancount[size_t(c)], 0u) << name;
            EXPECT_EQ(stats.infcount[size_t(c)], 0u) << name;
        }
    }
}

// A surface without the extension, or with a factor of 0, is no transmissive surface: no
// channel, a flat G-buffer.
TEST_F(TransmissionFiles, NoTransmissionNoChannel) {
    const nlohmann::json doc = paneBeforeWall({{"transmissionFactor", 0.0}}, 1.0);
    writeJson(path("none.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("none.gltf") +
                         " --lookat 0,0,3,0,0,0 --fov 60 --size 32x32 -o " + path("none.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const auto in = OIIO::ImageInput::open(path("none.exr"));
    ASSERT_TRUE(in);
    EXPECT_FALSE(in->spec().deep);
    EXPECT_LT(in->spec().channelindex("transmission"), 0);
}

} // namespace
