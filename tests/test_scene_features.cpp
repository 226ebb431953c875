// What the scene loader reads beyond geometry (issue 8, "smaller"): normal maps, emissive
// textures, KHR_texture_transform, the MTL's PBR extension, and a warning for what it leaves
// out. Each through dhdr-gbuffer, as a user meets it.
#include "scene_writer.h"
#include "tool_test.h"

#include <cmath>
#include <cstring>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/scene/scene.h>
#include <glm/glm.hpp>
#include <map>

using namespace dhdr::test;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

class SceneFeatures : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    // A constant 8-bit RGB PNG.
    static void writeConstantPng(const std::string& name, glm::vec3 value) {
        ImageBuf img(ImageSpec(4, 4, 3, TypeDesc::FLOAT));
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x)
                for (int c = 0; c < 3; ++c)
                    static_cast<float*>(img.pixeladdr(x, y))[c] = value[c];
        ASSERT_TRUE(img.write(path(name), TypeDesc::UINT8));
    }

    // The square of scene_writer.h with glTF UVs: u along +X, v down the image (−Y).
    static nlohmann::json texturedSquare() {
        GltfMesh mesh = squareMesh(1.0f);
        nlohmann::json doc = gltfWithMesh(mesh);
        // UVs as a second buffer: (−1,−1)→(0,1), (1,−1)→(1,1), (1,1)→(1,0), (−1,1)→(0,0).
        const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
        std::vector<std::uint8_t> bytes(sizeof uv);
        std::memcpy(bytes.data(), uv, sizeof uv);
        doc["buffers"].push_back(
            {{"byteLength", bytes.size()},
             {"uri", "data:application/octet-stream;base64," + base64(bytes)}});
        doc["bufferViews"].push_back({{"buffer", 1}, {"byteLength", bytes.size()}});
        doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1},
                                    {"componentType", 5126},
                                    {"count", 4},
                                    {"type", "VEC2"}});
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = doc["accessors"].size() - 1;
        doc["nodes"] = {{{"name", "square"}, {"mesh", 0}}};
        doc["scenes"] = {{{"nodes", {0}}}};
        return doc;
    }

    // The G-buffer's value of `channel` (3 components) at the centre pixel.
    static glm::vec3 centre(const std::string& file, const char* first) {
        const ImageBuf g = read(file);
        const int c = g.spec().channelindex(first);
        EXPECT_GE(c, 0) << first;
        const float* p = static_cast<const float*>(g.pixeladdr(8, 8));
        return {p[c], p[c + 1], p[c + 2]};
    }
};

} // namespace

// A tangent-space normal map: N = normalize(T·x + B·y + N·z), with T along +u (+X here) and
// B up the image (+Y here). Both halves of the map are checked, so a wrong bitangent sign fails.
TEST_F(SceneFeatures, NormalMapsBendTheGBufferNormal) {
    for (const auto& [name, encoded, expected] :
         std::vector<std::tuple<std::string, glm::vec3, glm::vec3>>{
             {"x", {0.8f, 0.5f, 0.9f}, {0.6f, 0.0f, 0.8f}},
             {"y", {0.5f, 0.8f, 0.9f}, {0.0f, 0.6f, 0.8f}}}) {
        writeConstantPng("normal_" + name + ".png", encoded);
        nlohmann::json doc = texturedSquare();
        doc["images"] = {{{"uri", "normal_" + name + ".png"}}};
        doc["textures"] = {{{"source", 0}}};
        doc["materials"][0]["normalTexture"] = {{"index", 0}};
        writeJson(path("normal_" + name + ".gltf"), doc);
        const Result r = run("dhdr-gbuffer " + path("normal_" + name + ".gltf") +
                             " --lookat 0,0,3,0,0,0 --size 16x16 -o " + path("n.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
        const glm::vec3 n = centre("n.exr", "N.X");
        // 8-bit encoding of 0.8/0.5/0.9: within 0.01 of the exact map.
        EXPECT_NEAR(n.x, expected.x, 0.01) << name;
        EXPECT_NEAR(n.y, expected.y, 0.01) << name;
        EXPECT_NEAR(n.z, expected.z, 0.01) << name;
    }
}

// emission = emissiveFactor × strength × the sRGB-decoded emissive texture.
TEST_F(SceneFeatures, EmissiveTexturesScaleEmission) {
    writeConstantPng("glow.png", {1.0f, 0.5f, 0.0f});
    nlohmann::json doc = texturedSquare();
    doc["images"] = {{{"uri", "glow.png"}}};
    doc["textures"] = {{{"source", 0}}};
    doc["materials"][0]["emissiveTexture"] = {{"index", 0}};
    doc["materials"][0]["emissiveFactor"] = {2.0, 2.0, 2.0};
    writeJson(path("glow.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("glow.gltf") +
                         " --lookat 0,0,3,0,0,0 --size 16x16 -o " + path("e.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const glm::vec3 e = centre("e.exr", "emission.R");
    const double half = std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4); // 8-bit 0.5, decoded
    EXPECT_NEAR(e.x, 2.0, 1e-3);
    EXPECT_NEAR(e.y, 2.0 * half, 1e-3);
    EXPECT_NEAR(e.z, 0.0, 1e-3);
}

// KHR_texture_transform, as the extension defines it: translation · rotation · scale, the
// rotation's sign as Khronos' TextureTransformTest model shows it (docs/scenes.md).
TEST(TextureTransform, IsTranslationRotationScale) {
    dhdr::TextureTransform t;
    t.offset = {0.25f, -0.5f};
    t.rotation = 0.392699f;
    t.scale = {1.5f, 0.5f};
    const glm::vec2 uv(0.3f, 0.7f);
    const double c = std::cos(0.392699), s = std::sin(0.392699);
    const double su = 0.3 * 1.5, sv = 0.7 * 0.5;
    const glm::vec2 out = t.apply(uv);
    EXPECT_NEAR(out.x, c * su + s * sv + 0.25, 1e-6);
    EXPECT_NEAR(out.y, -s * su + c * sv - 0.5, 1e-6);
    EXPECT_EQ(dhdr::TextureTransform{}.apply(uv), uv);
}

// An offset of half the texture moves a two-colour texture's halves: at the square's left
// half (u < 0.5) the right half of the texture shows.
TEST_F(SceneFeatures, TextureTransformMovesTheBaseColour) {
    ImageBuf img(ImageSpec(2, 1, 3, TypeDesc::FLOAT));
    const float red[3] = {1, 0, 0}, blue[3] = {0, 0, 1};
    std::copy(red, red + 3, static_cast<float*>(img.pixeladdr(0, 0)));
    std::copy(blue, blue + 3, static_cast<float*>(img.pixeladdr(1, 0)));
    ASSERT_TRUE(img.write(path("halves.png"), TypeDesc::UINT8));
    for (const double offset : {0.0, 0.5}) {
        nlohmann::json doc = texturedSquare();
        doc["images"] = {{{"uri", "halves.png"}}};
        doc["textures"] = {{{"source", 0}}};
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1, 1};
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {
            {"index", 0}, {"extensions", {{"KHR_texture_transform", {{"offset", {offset, 0.0}}}}}}};
        doc["extensionsUsed"] = {"KHR_texture_transform"};
        writeJson(path("halves.gltf"), doc);
        const Result r = run("dhdr-gbuffer " + path("halves.gltf") +
                             " --lookat 0,0,2.5,0,0,0 --fov 60 --size 64x64 -o " + path("t.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(r.err.find("not read"), std::string::npos) << r.err;
        const ImageBuf g = read("t.exr");
        const int a = g.spec().channelindex("albedo.R");
        // A quarter of the way in from the left edge of the square: u ≈ 0.25.
        const float* p = static_cast<const float*>(g.pixeladdr(21, 32));
        ASSERT_EQ(p[0], 1.0f);
        if (offset == 0.0)
            EXPECT_GT(p[a], 0.9f); // red
        else
            EXPECT_GT(p[a + 2], 0.9f); // blue
    }
}

// Blender's OBJ export of a gold material, as Blender 3.6 writes its MTL: Pm 1 makes it
// metallic, Pr its roughness. Assimp 5.2 stops at Blender's `aniso` lines unless they are
// left out of what it reads (scene_loader.cpp).
TEST_F(SceneFeatures, ObjPbrExtensionIsRead) {
    std::ofstream(path("gold.mtl"))
        << "# Blender 3.6 MTL File: 'gold.blend'\n# www.blender.org\n\nnewmtl Gold\n"
           "Ns 250.000000\nKa 1.000000 1.000000 1.000000\nKs 0.500000 0.500000 0.500000\n"
           "Ke 0.000000 0.000000 0.000000\nNi 1.450000\nd 1.000000\nillum 3\nPr 0.300000\n"
           "Pm 1.000000\nPs 0.000000\nPc 0.000000\nPcr 0.030000\naniso 0.000000\n"
           "anisor 0.000000\nKd 1.000000 0.766000 0.336000\n\nnewmtl Plain\nKd 0.5 0.5 0.5\n";
    std::ofstream(path("gold.obj")) << "mtllib gold.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                                       "usemtl Gold\nf 1 2 3\nusemtl Plain\nf 1 3 4\n";
    const Result r = run("dhdr-gbuffer " + path("gold.obj") +
                         " --lookat 0,0,3,0,0,0 --size 32x32 -o " + path("gold.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf g = read("gold.exr");
    const int metallic = g.spec().channelindex("metallic");
    const int roughness = g.spec().channelindex("roughness");
    // The lower-right triangle is Gold, the upper-left Plain.
    const float* gold = static_cast<const float*>(g.pixeladdr(24, 20));
    const float* plain = static_cast<const float*>(g.pixeladdr(8, 12));
    ASSERT_EQ(gold[0], 1.0f);
    ASSERT_EQ(plain[0], 1.0f);
    EXPECT_EQ(gold[metallic], 1.0f);
    EXPECT_NEAR(gold[roughness], 0.3f, 1e-3);
    EXPECT_EQ(plain[metallic], 0.0f);
}

// What stays unsupported is one warning line per kind, naming it.
TEST_F(SceneFeatures, IgnoredFeaturesAreNamed) {
    nlohmann::json doc = texturedSquare();
    doc["extensionsUsed"] = {"KHR_materials_iridescence", "KHR_texture_transform",
                             "EXT_mesh_gpu_instancing"};
    doc["skins"] = nlohmann::json::array({{{"joints", {0}}}});
    writeJson(path("unsupported.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("unsupported.gltf") +
                         " --lookat 0,0,3,0,0,0 --size 8x8 -o " + path("u.exr"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("glTF extensions not read: KHR_materials_iridescence, "
                         "EXT_mesh_gpu_instancing"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("skins are not applied"), std::string::npos) << r.err;
}

// --info tells what a scene holds without rendering it.
TEST_F(SceneFeatures, InfoDescribesTheScene) {
    const Result r = run("dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --info");
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* what : {"bounds", "objects     8,", "cameras     1", "perspective",
                             "lights      2", "materials   4", "white", "left out    nothing"})
        EXPECT_NE(r.out.find(what), std::string::npos) << what << " in:\n" << r.out;
}

// --frame-all places a camera from which the whole scene is in view, even when the scene
// has none: every corner of a 2 × 2 square is covered, and no pixel on the image's border.
TEST_F(SceneFeatures, FrameAllFitsTheWholeScene) {
    nlohmann::json doc = gltfWithMesh(squareMesh(1.0f));
    doc["nodes"] = {{{"name", "square"}, {"mesh", 0}, {"translation", {5.0, -2.0, 1.0}}}};
    doc["scenes"] = {{{"nodes", {0}}}};
    writeJson(path("nocamera.gltf"), doc);
    Result r = run("dhdr-gbuffer " + path("nocamera.gltf") + " -o " + path("nc.exr"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("--frame-all"), std::string::npos) << r.err;
    r = run("dhdr-gbuffer " + path("nocamera.gltf") + " --frame-all --size 48x32 -o " +
            path("fa.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf g = read("fa.exr");
    const int px = g.spec().channelindex("P.X"), py = g.spec().channelindex("P.Y");
    float xmin = 1e9f, xmax = -1e9f, ymin = 1e9f, ymax = -1e9f;
    int border = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 48; ++x) {
            const float* p = static_cast<const float*>(g.pixeladdr(x, y));
            if (p[0] == 0.0f) continue;
            border += x == 0 || y == 0 || x == 47 || y == 31;
            xmin = std::min(xmin, p[px]);
            xmax = std::max(xmax, p[px]);
            ymin = std::min(ymin, p[py]);
            ymax = std::max(ymax, p[py]);
        }
    EXPECT_EQ(border, 0);
    // The square spans x in [4, 6], y in [−3, −1]; pixel centres reach within a pixel of it.
    EXPECT_LT(xmin, 4.15f);
    EXPECT_GT(xmax, 5.85f);
    EXPECT_LT(ymin, -2.85f);
    EXPECT_GT(ymax, -1.15f);
}

// An OBJ written on Windows names its texture with a backslash: found all the same.
TEST_F(SceneFeatures, WindowsTexturePathsAreFound) {
    writeConstantPng("red.png", {1.0f, 0.0f, 0.0f});
    std::ofstream(path("win.mtl")) << "newmtl M\nKd 1 1 1\nmap_Kd .\\red.png\n";
    std::ofstream(path("win.obj")) << "mtllib win.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\n"
                                      "vt 0 0\nvt 1 0\nvt 1 1\nusemtl M\nf 1/1 2/2 3/3\n";
    const Result r = run("dhdr-gbuffer " + path("win.obj") +
                         " --lookat 0,0,3,0,0,0 --size 32x32 -o " + path("win.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf g = read("win.exr");
    const int a = g.spec().channelindex("albedo.R");
    const float* p = static_cast<const float*>(g.pixeladdr(20, 20));
    ASSERT_EQ(p[0], 1.0f);
    EXPECT_NEAR(p[a], 1.0f, 1e-3);
    EXPECT_NEAR(p[a + 1], 0.0f, 1e-3);
}

namespace {

// MurmurHash3_x86_32 (seed 0) of each name from Debian's python3-murmurhash, an implementation
// apart from OpenEXR's that dhdr uses.
std::vector<std::uint32_t> pythonMurmur(const std::vector<std::string>& names,
                                        const std::string& scratch) {
    {
        std::ofstream list(scratch + "/names.json");
        list << nlohmann::json(names).dump();
    }
    const std::string cmd =
        "/usr/bin/python3 -c \"import json,sys; from murmurhash import mrmr; "
        "print(' '.join(str(mrmr.hash(n) & 0xffffffff) for n in json.load(open('" +
        scratch + "/names.json'))))\" > " + scratch + "/hashes.txt";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream in(scratch + "/hashes.txt");
    std::vector<std::uint32_t> out;
    for (unsigned long h; in >> h;)
        out.push_back(std::uint32_t(h));
    EXPECT_EQ(out.size(), names.size());
    return out;
}

std::uint32_t floatBits(float f) {
    std::uint32_t h;
    std::memcpy(&h, &f, sizeof h);
    return h;
}

} // namespace

TEST_F(SceneFeatures, CryptomatteIdsAreMurmurHashesAsTheSpecSays) {
    // The spec's example and a few thousand names against an independent MurmurHash3, with the
    // exponent rule applied here: bit 23 flipped where the exponent would be 0 or 255.
    EXPECT_EQ(floatBits(dhdr::gbuffer::cryptomatteId("torus")), 0xf19c73fdu);
    std::vector<std::string> names = {"torus", "tall_block", "dhdr:ground plane", "ünïcødé"};
    for (int i = 0; i < 3000; ++i)
        names.push_back("object_" + std::to_string(i));
    const std::vector<std::uint32_t> hashes = pythonMurmur(names, dir.string());
    ASSERT_EQ(hashes.size(), names.size());
    int flipped = 0;
    for (size_t i = 0; i < names.size(); ++i) {
        std::uint32_t h = 0;
        const float id = dhdr::gbuffer::cryptomatteId(names[i], &h);
        ASSERT_EQ(h, hashes[i]) << names[i];
        std::uint32_t expected = hashes[i];
        const std::uint32_t exponent = (expected >> 23) & 255u;
        if (exponent == 0 || exponent == 255) {
            expected ^= 1u << 23;
            ++flipped;
        }
        ASSERT_EQ(floatBits(id), expected) << names[i];
        ASSERT_TRUE(std::isfinite(id) && std::fpclassify(id) != FP_SUBNORMAL) << names[i];
    }
    EXPECT_GT(flipped, 0) << "the names must include some whose exponent needs the flip";
}

TEST_F(SceneFeatures, GBufferCarriesCryptomatteLayersAndManifests) {
    const std::string g = path("crypto.exr");
    ASSERT_EQ(run("dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --size 64x64 -o " + g).status,
              0);
    ImageBuf img(g);
    ASSERT_TRUE(img.read(0, 0, true, OIIO::TypeDesc::FLOAT));
    const OIIO::ImageSpec& spec = img.spec();
    // The layers' metadata, keyed by the first 7 hex digits of the layer name's hash.
    const std::vector<std::uint32_t> layerHashes =
        pythonMurmur({"CryptoObject", "CryptoMaterial"}, dir.string());
    ASSERT_EQ(layerHashes.size(), 2u);
    std::map<std::string, std::uint32_t> objectHash;
    std::vector<std::string> objectNames;
    for (int k = 0; k < 2; ++k) {
        char key[16];
        std::snprintf(key, sizeof key, "%08x", layerHashes[size_t(k)]);
        const std::string prefix = "cryptomatte/" + std::string(key, 7) + "/";
        EXPECT_EQ(spec.get_string_attribute(prefix + "name"),
                  k == 0 ? "CryptoObject" : "CryptoMaterial");
        EXPECT_EQ(spec.get_string_attribute(prefix + "hash"), "MurmurHash3_32");
        EXPECT_EQ(spec.get_string_attribute(prefix + "conversion"), "uint32_to_float32");
        const nlohmann::json manifest =
            nlohmann::json::parse(spec.get_string_attribute(prefix + "manifest"));
        ASSERT_TRUE(manifest.is_object());
        std::vector<std::string> names;
        for (const auto& [name, hex] : manifest.items())
            names.push_back(name);
        const std::vector<std::uint32_t> hashes = pythonMurmur(names, dir.string());
        for (size_t i = 0; i < names.size(); ++i) {
            char hex[16];
            std::snprintf(hex, sizeof hex, "%08x", hashes[i]);
            EXPECT_EQ(manifest[names[i]].get<std::string>(), hex) << names[i];
            if (k == 0) objectHash[names[i]] = hashes[i];
        }
        if (k == 0) objectNames = names;
    }
    ASSERT_TRUE(objectHash.count("tall_block"));
    // Pixels: rank 0 is the object the id channel names, with coverage 1; coverages sum to at
    // most 1; a matte by name equals that object's pixels.
    const int r = spec.channelindex("CryptoObject00.r"), idc = spec.channelindex("id.object");
    ASSERT_GE(r, 0);
    ASSERT_EQ(spec.channelformat(r), OIIO::TypeDesc::FLOAT);
    const OIIO::ParamValue* table = spec.find_attribute("dhdr:objectNames");
    ASSERT_TRUE(table);
    const auto* tableNames = static_cast<const char* const*>(table->data());
    std::uint32_t tall = objectHash["tall_block"];
    if (((tall >> 23) & 255u) == 0 || ((tall >> 23) & 255u) == 255) tall ^= 1u << 23;
    int matte = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const float id = img.getchannel(x, y, 0, r), cov0 = img.getchannel(x, y, 0, r + 1);
            const float cov1 = img.getchannel(x, y, 0, r + 3);
            EXPECT_LE(cov0 + cov1, 1.0f);
            // OpenImageIO reads a uint channel as float scaled from [0, 2³² − 1] to [0, 1].
            const int object =
                int(std::lround(double(img.getchannel(x, y, 0, idc)) * 4294967295.0));
            if (object == 0) {
                EXPECT_EQ(cov0, 0.0f);
                continue;
            }
            EXPECT_EQ(cov0, 1.0f);
            const std::string name = tableNames[object];
            std::uint32_t h = objectHash[name];
            if (((h >> 23) & 255u) == 0 || ((h >> 23) & 255u) == 255) h ^= 1u << 23;
            EXPECT_EQ(floatBits(id), h) << name;
            const bool inMatte = floatBits(id) == tall && cov0 > 0.0f;
            EXPECT_EQ(inMatte, name == "tall_block");
            matte += inMatte;
        }
    EXPECT_GT(matte, 100);
}
