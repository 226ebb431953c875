// Hostile scenes (issue 21): broken cameras, coordinates at infinity, deep node trees, meshes
// without normals, unnamed objects and missing textures. Each is a small glTF this file writes
// (scene_writer.h), run through dhdr-gbuffer as a user runs it, or through loadScene where the
// loader's result is the point.
#include "scene_writer.h"
#include "tool_test.h"

#include <cmath>
#include <cstring>
#include <dhdr/deferred/scene/scene.h>
#include <glm/glm.hpp>
#include <limits>
#include <pthread.h>
#include <tuple>

using namespace dhdr::test;

namespace {

class SceneInput : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    // `r` failed with exit status 1, saying `what`, and left neither `out` nor a temporary.
    static void expectRefused(const Result& r, const std::string& what, const std::string& out) {
        EXPECT_EQ(r.status, 1) << r.err;
        EXPECT_NE(r.err.find(what), std::string::npos) << "expected '" << what << "' in: " << r.err;
        EXPECT_FALSE(fs::exists(out)) << out;
        EXPECT_TRUE(noTemporaries());
    }

    // The square of scene_writer.h and a perspective camera `camera` on the node `node`.
    static nlohmann::json squareWithCamera(const nlohmann::json& camera,
                                           const nlohmann::json& node) {
        nlohmann::json doc = gltfWithMesh(squareMesh());
        doc["cameras"] = {camera};
        nlohmann::json cameraNode = node;
        cameraNode["name"] = "shot";
        cameraNode["camera"] = 0;
        doc["nodes"] = {{{"name", "square"}, {"mesh", 0}}, cameraNode};
        doc["scenes"] = {{{"nodes", {0, 1}}}};
        return doc;
    }
};

const nlohmann::json kGoodPerspective = {
    {"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}, {"zfar", 100.0}}}};

} // namespace

// A camera node scaled by 0 aborted inside Embree (NaN rays); a field of view of 0, a znear of
// 0, a zfar before znear, a negative ymag: each is refused naming the file and the camera, and
// --info says why. A good camera on the same square renders.
TEST_F(SceneInput, DegenerateCamerasAreRefused) {
    const nlohmann::json at = {{"translation", {0.0, 0.0, 3.0}}};
    nlohmann::json perspective = kGoodPerspective;
    writeJson(path("good_camera.gltf"), squareWithCamera(perspective, at));
    const Result good =
        run("dhdr-gbuffer " + path("good_camera.gltf") + " --size 8x8 -o " + path("good.exr"));
    ASSERT_EQ(good.status, 0) << good.err;

    struct Case {
        std::string name;
        nlohmann::json camera, node;
        std::string why;
        bool fileRefused = false; // Assimp refuses the whole file, not just the camera
    };
    std::vector<Case> cases;
    nlohmann::json scaled = at;
    scaled["scale"] = {0.0, 0.0, 0.0};
    cases.push_back({"scale0", perspective, scaled, "camera-to-world matrix is not invertible"});
    nlohmann::json flat = at;
    flat["scale"] = {1.0, 0.0, 1.0};
    cases.push_back({"flat", perspective, flat, "camera-to-world matrix is not invertible"});
    nlohmann::json c = perspective;
    c["perspective"]["yfov"] = 0.0;
    cases.push_back({"yfov0", c, at, "vertical field of view, 0 degrees"});
    c = perspective;
    c["perspective"]["yfov"] = 4.0;
    cases.push_back({"yfov4", c, at, "is not between 0 and 180"});
    c = perspective;
    c["perspective"]["znear"] = 0.0;
    cases.push_back({"znear0", c, at, "its znear, 0, is not a positive number"});
    c = perspective;
    c["perspective"]["zfar"] = 0.05;
    cases.push_back({"zfar", c, at, "its zfar, 0.05, is not greater than its znear", true});
    c = perspective;
    c["perspective"]["aspectRatio"] = 0.0;
    cases.push_back({"aspect0", c, at, "its aspectRatio, 0.0, is not a positive number"});
    c = perspective;
    c["perspective"]["yfov"] = "wide";
    cases.push_back({"yfovstring", c, at, "\"yfov\" must be a number"});
    c = perspective;
    c["perspective"]["znear"] = 1e39; // beyond a float
    c["perspective"]["zfar"] = 1e40;
    cases.push_back({"znearhuge", c, at, "\"znear\" must be a number a float holds", true});
    const nlohmann::json ortho = {
        {"type", "orthographic"},
        {"orthographic", {{"xmag", 1.0}, {"ymag", -1.0}, {"znear", 0.0}, {"zfar", 10.0}}}};
    cases.push_back({"ymag", ortho, at, "its ymag, -1, is not a positive number"});
    nlohmann::json huge = at;
    huge["translation"] = {0.0, 0.0, 1e39};
    cases.push_back({"far", perspective, huge, "is not finite"});

    for (const Case& k : cases) {
        const std::string file = path("camera_" + k.name + ".gltf");
        const std::string out = path("camera_" + k.name + ".exr");
        writeJson(file, squareWithCamera(k.camera, k.node));
        const Result refused = run("dhdr-gbuffer " + file + " --size 8x8 -o " + out);
        expectRefused(refused, file + ": camera 'shot' cannot be rendered from: ", out);
        EXPECT_NE(refused.err.find(k.why), std::string::npos) << k.name << ": " << refused.err;
        // --frame-all keeps the camera's direction: a camera without one is refused too.
        expectRefused(run("dhdr-gbuffer " + file + " --frame-all --size 8x8 -o " + out),
                      "camera 'shot' cannot be rendered from", out);
        if (k.fileRefused) continue;
        // A camera given on the command line replaces it; --info tells what is wrong.
        EXPECT_EQ(run("dhdr-gbuffer " + file + " --lookat 0,0,3,0,0,0 --size 8x8 -o " + out).status,
                  0)
            << k.name;
        fs::remove(out);
        const Result info = run("dhdr-gbuffer " + file + " --info");
        EXPECT_EQ(info.status, 0) << info.err;
        EXPECT_NE(info.out.find("unusable: "), std::string::npos) << k.name << ": " << info.out;
    }
}

// A vertex at infinity (written as the float +Inf, which JSON cannot spell but a buffer can):
// an error naming the mesh, with or without --frame-all (which wrote NaN matrices with exit 0).
// A node scaled so that finite vertices leave the float range is refused the same way.
TEST_F(SceneInput, NonFiniteVerticesAreAnErrorNamingTheMesh) {
    GltfMesh mesh = squareMesh();
    mesh.positions[2][2] = std::numeric_limits<float>::infinity();
    nlohmann::json doc = gltfWithMesh(mesh);
    doc["accessors"][0].erase("min");
    doc["accessors"][0].erase("max");
    doc["nodes"] = {{{"name", "square"}, {"mesh", 0}}};
    doc["scenes"] = {{{"nodes", {0}}}};
    writeJson(path("inf.gltf"), doc);
    for (const std::string options : {" --lookat 0,0,3,0,0,0", " --frame-all"})
        expectRefused(
            run("dhdr-gbuffer " + path("inf.gltf") + options + " --size 8x8 -o " + path("inf.exr")),
            path("inf.gltf") + ": mesh 'mesh' (node 'square'): vertex 2 is not a finite "
                               "position in world space",
            path("inf.exr"));

    doc = gltfWithMesh(squareMesh(2.0f));
    doc["nodes"] = {{{"name", "square"}, {"mesh", 0}, {"scale", {3e38, 3e38, 3e38}}}};
    doc["scenes"] = {{{"nodes", {0}}}};
    writeJson(path("overflow.gltf"), doc);
    expectRefused(run("dhdr-gbuffer " + path("overflow.gltf") + " --frame-all --size 8x8 -o " +
                      path("overflow.exr")),
                  "mesh 'mesh' (node 'square'): vertex 0 is not a finite position",
                  path("overflow.exr"));
}

// Finite vertices whose bounding sphere no float camera can frame: --frame-all says so (it
// wrote a G-buffer with infinite matrices and no surface, exit 0).
TEST_F(SceneInput, FrameAllRefusesBoundsNoCameraCanFrame) {
    GltfMesh mesh = squareMesh();
    mesh.positions = {
        {-3e38f, -3e38f, 0}, {3e38f, -3e38f, 0}, {3e38f, 3e38f, 0}, {-3e38f, 3e38f, 0}};
    nlohmann::json doc = gltfWithMesh(mesh);
    doc["nodes"] = {{{"name", "square"}, {"mesh", 0}}};
    doc["scenes"] = {{{"nodes", {0}}}};
    writeJson(path("vast.gltf"), doc);
    expectRefused(
        run("dhdr-gbuffer " + path("vast.gltf") + " --frame-all --size 8x8 -o " + path("vast.exr")),
        path("vast.gltf") + ": --frame-all cannot frame the scene's bounds, (-3e+38, -3e+38, 0) to "
                            "(3e+38, 3e+38, 0)",
        path("vast.exr"));
}

namespace {

// `doc` as a binary glTF: header, JSON chunk, and its buffer 0 (a data URI in `doc`) as the
// BIN chunk, which is how Assimp 5.2 reads a .glb's buffer.
void writeGlb(const std::string& file, nlohmann::json doc) {
    const std::string uri = doc["buffers"][0]["uri"].get<std::string>();
    const std::string b64 = uri.substr(uri.find(',') + 1);
    std::string bin;
    std::uint32_t bits = 0;
    int count = 0;
    for (const char ch : b64) {
        const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        const char* at = std::strchr(table, ch);
        if (ch == '=' || !at) break;
        bits = bits << 6 | std::uint32_t(at - table);
        if (++count % 4 == 0)
            for (int k = 2; k >= 0; --k)
                bin += char((bits >> (8 * k)) & 255u);
    }
    if (count % 4 == 3) {
        bin += char((bits >> 10) & 255u);
        bin += char((bits >> 2) & 255u);
    } else if (count % 4 == 2) {
        bin += char((bits >> 4) & 255u);
    }
    doc["buffers"][0].erase("uri");
    while (bin.size() % 4 != 0)
        bin += '\0';
    std::string text = doc.dump();
    while (text.size() % 4 != 0)
        text += ' ';
    const std::uint32_t header[5] = {0x46546C67u, 2u,
                                     std::uint32_t(12 + 8 + text.size() + 8 + bin.size()),
                                     std::uint32_t(text.size()), 0x4E4F534Au};
    const std::uint32_t binHeader[2] = {std::uint32_t(bin.size()), 0x004E4942u};
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(header), sizeof header);
    out.write(text.data(), std::streamsize(text.size()));
    out.write(reinterpret_cast<const char*>(binHeader), sizeof binHeader);
    out.write(bin.data(), std::streamsize(bin.size()));
}

// 15,000 nodes, each the only child of the one before and 0.0001 to the right of it, the
// square at the bottom and a camera 3 units in front of it; 1.5 to the right in all.
nlohmann::json deepNodes(int depth) {
    nlohmann::json doc = gltfWithMesh(squareMesh());
    doc["cameras"] = {kGoodPerspective};
    nlohmann::json nodes = nlohmann::json::array();
    for (int i = 0; i < depth; ++i)
        nodes.push_back({{"name", "n" + std::to_string(i)},
                         {"translation", {1e-4, 0.0, 0.0}},
                         {"children", {i + 1}}});
    nodes.push_back({{"name", "leaf"}, {"children", {depth + 1, depth + 2}}});
    nodes.push_back({{"name", "square"}, {"mesh", 0}});
    nodes.push_back({{"name", "shot"}, {"camera", 0}, {"translation", {0.0, 0.0, 3.0}}});
    doc["nodes"] = nodes;
    doc["scenes"] = {{{"nodes", {0}}}};
    return doc;
}

} // namespace

// 15,000 nested nodes overflowed the stack inside Assimp 5.2's recursive glTF reader (a
// segfault at 40,000 nodes, or at 15,000 on a 2 MiB stack): a deep tree is handed to it
// flattened, transforms composed, so the square and the camera are where the file puts them,
// from a .gltf and a .glb alike. A cycle, which Assimp would recurse on forever, is an error.
TEST_F(SceneInput, DeeplyNestedNodesLoadWithTheirTransforms) {
    const nlohmann::json doc = deepNodes(15000);
    writeJson(path("deep.gltf"), doc);
    writeGlb(path("deep.glb"), doc);
    for (const char* name : {"deep.gltf", "deep.glb"}) {
        const Result r = run("dhdr-gbuffer " + path(name) + " --size 16x16 -o " + path("deep.exr"));
        ASSERT_EQ(r.status, 0) << name << ": " << r.err;
        const ImageBuf g = read("deep.exr");
        const int px = g.spec().channelindex("P.X"), pz = g.spec().channelindex("P.Z");
        const float* p = static_cast<const float*>(g.pixeladdr(8, 8));
        ASSERT_EQ(p[0], 1.0f) << name;
        EXPECT_NEAR(p[px], 1.5f, 0.1f) << name; // the pixel's centre is off the axis by 1/16
        EXPECT_NEAR(p[pz], 0.0f, 1e-4f) << name;
        const Result info = run("dhdr-gbuffer " + path(name) + " --info");
        EXPECT_NE(info.out.find("shot: perspective"), std::string::npos) << info.out;
        EXPECT_NE(info.out.find("at (1.5, 0, 3)"), std::string::npos) << info.out;
    }

    // In a thread with a 1 MiB stack, as a host program might call the library.
    struct Call {
        std::string path, error;
        dhdr::Scene scene;
        bool ok = false;
    } call{path("deep100k.gltf"), {}, {}, false};
    writeJson(call.path, deepNodes(100000));
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, size_t(1) << 20);
    pthread_t thread;
    ASSERT_EQ(pthread_create(
                  &thread, &attr,
                  [](void* arg) -> void* {
                      auto* c = static_cast<Call*>(arg);
                      c->ok = dhdr::loadScene(c->path, c->scene, c->error);
                      return nullptr;
                  },
                  &call),
              0);
    pthread_join(thread, nullptr);
    pthread_attr_destroy(&attr);
    ASSERT_TRUE(call.ok) << call.error;
    ASSERT_EQ(call.scene.meshes.size(), 1u);
    EXPECT_NEAR(call.scene.boundsMin().x, 9.0, 1e-3); // 100,000 × 0.0001 − 1
    ASSERT_EQ(call.scene.cameras.size(), 1u);
    EXPECT_NEAR(call.scene.cameras[0].camera.position().x, 10.0, 1e-3);

    nlohmann::json cycle = deepNodes(3);
    cycle["nodes"][2]["children"] = {1};
    writeJson(path("cycle.gltf"), cycle);
    expectRefused(run("dhdr-gbuffer " + path("cycle.gltf") + " --size 8x8 -o " + path("cycle.exr")),
                  path("cycle.gltf") +
                      ": cannot load the scene: node 1 is its own ancestor (the nodes form a cycle",
                  path("cycle.exr"));
}

namespace {

// A 2 × 2 × 2 box around the origin, its 8 corners shared by the 12 triangles (wound
// counter-clockwise seen from outside), without normals.
GltfMesh boxWithoutNormals() {
    GltfMesh m;
    m.positions = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                   {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    m.indices = {4, 5, 6, 4, 6, 7, 0, 2, 1, 0, 3, 2, 1, 2, 6, 1, 6, 5,
                 0, 4, 7, 0, 7, 3, 3, 7, 6, 3, 6, 2, 0, 1, 5, 0, 5, 4};
    return m;
}

} // namespace

// glTF 2.0 §3.7.2.1: a primitive without normals gets flat normals (smoothed ones made the box
// a blob: corner normals along the diagonals). Every covered pixel's N is the outward normal
// of the face it sees, the face told by P (the coordinate at ±1), under a plain node and under
// a mirroring one (which reverses the winding, glTF §3.7.4); the three faces in view all show.
// A primitive with normals keeps the file's.
TEST_F(SceneInput, MeshesWithoutNormalsGetFlatNormals) {
    for (const bool mirrored : {false, true}) {
        nlohmann::json doc = gltfWithMesh(boxWithoutNormals());
        doc["nodes"] = {{{"name", "box"}, {"mesh", 0}}};
        if (mirrored) doc["nodes"][0]["scale"] = {-1.0, 1.0, 1.0};
        doc["scenes"] = {{{"nodes", {0}}}};
        writeJson(path("box.gltf"), doc);
        const Result r = run("dhdr-gbuffer " + path("box.gltf") +
                             " --lookat 3,2.5,4,0,0,0 --size 48x48 -o " + path("box.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(r.err.find("zero length"), std::string::npos) << r.err;
        const ImageBuf g = read("box.exr");
        const int p0 = g.spec().channelindex("P.X"), n0 = g.spec().channelindex("N.X");
        ASSERT_GE(p0, 0);
        ASSERT_GE(n0, 0);
        int faces[3] = {0, 0, 0}, wrong = 0;
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 48; ++x) {
                const float* px = static_cast<const float*>(g.pixeladdr(x, y));
                if (px[0] == 0.0f) continue;
                const glm::vec3 p(px[p0], px[p0 + 1], px[p0 + 2]);
                const glm::vec3 n(px[n0], px[n0 + 1], px[n0 + 2]);
                const glm::vec3 a = glm::abs(p);
                const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
                // On an edge the face is ambiguous.
                if (a[(axis + 1) % 3] > 0.97f || a[(axis + 2) % 3] > 0.97f) continue;
                glm::vec3 expected(0.0f);
                expected[axis] = p[axis] > 0.0f ? 1.0f : -1.0f;
                ++faces[axis];
                wrong += glm::length(n - expected) > 1e-5f;
                if (wrong == 1 && glm::length(n - expected) > 1e-5f)
                    ADD_FAILURE() << "mirrored " << mirrored << " pixel " << x << "," << y
                                  << ": N (" << n.x << ", " << n.y << ", " << n.z << ")";
            }
        EXPECT_EQ(wrong, 0) << "mirrored " << mirrored;
        for (int axis = 0; axis < 3; ++axis)
            EXPECT_GT(faces[axis], 50) << "axis " << axis << ", mirrored " << mirrored;
    }

    GltfMesh tilted = squareMesh();
    for (auto& n : tilted.normals)
        n = {0.6f, 0.0f, 0.8f};
    nlohmann::json doc = gltfWithMesh(tilted);
    doc["nodes"] = {{{"name", "square"}, {"mesh", 0}}};
    doc["scenes"] = {{{"nodes", {0}}}};
    writeJson(path("tilted.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("tilted.gltf") +
                         " --lookat 0,0,3,0,0,0 --size 16x16 -o " + path("tilted.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf g = read("tilted.exr");
    const int n0 = g.spec().channelindex("N.X");
    const float* px = static_cast<const float*>(g.pixeladdr(8, 8));
    ASSERT_EQ(px[0], 1.0f);
    EXPECT_NEAR(px[n0], 0.6f, 1e-3f); // N is stored as half
    EXPECT_NEAR(px[n0 + 1], 0.0f, 1e-3f);
    EXPECT_NEAR(px[n0 + 2], 0.8f, 1e-3f);
}

namespace {

// The Cryptomatte manifest of `layer` in the G-buffer's header, as text.
std::string manifestOf(const OIIO::ImageSpec& spec, const std::string& layer) {
    for (const OIIO::ParamValue& p : spec.extra_attribs)
        if (p.name().string().rfind("cryptomatte/", 0) == 0 && p.name().string().size() > 20 &&
            p.name().string().compare(p.name().string().size() - 5, 5, "/name") == 0 &&
            spec.get_string_attribute(p.name().string()) == layer)
            return spec.get_string_attribute(
                p.name().string().substr(0, p.name().string().size() - 4) + "manifest");
    return {};
}

// A G-buffer header's name table (dhdr:objectNames, dhdr:materialNames).
std::vector<std::string> nameTable(const OIIO::ImageSpec& spec, const char* attribute) {
    std::vector<std::string> out;
    const OIIO::ParamValue* table = spec.find_attribute(attribute);
    if (!table) return out;
    const auto* names = static_cast<const char* const*>(table->data());
    for (int i = 0; i < table->nvalues() * int(table->type().numelements()); ++i)
        out.push_back(names[i]);
    return out;
}

} // namespace

// Unnamed objects and materials made a Cryptomatte manifest entry "" (twice, for two of them):
// they are named as Blender names datablocks, from the mesh's name, else "Object",
// "Object.001"..., "Material", "Material.001"..., and a name the file gives twice gets ".001"
// the second time; the same names in dhdr:objectNames / dhdr:materialNames and the manifests.
TEST_F(SceneInput, UnnamedObjectsAndMaterialsGetBlenderNames) {
    nlohmann::json doc = gltfWithMesh(squareMesh(0.4f));
    const nlohmann::json primitive = doc["meshes"][0]["primitives"][0];
    doc["meshes"][0].erase("name");
    nlohmann::json named = {{"name", "crate"}, {"primitives", {primitive}}};
    named["primitives"][0]["material"] = 1;
    doc["meshes"].push_back(named);
    nlohmann::json noMaterial = {{"primitives", {primitive}}};
    noMaterial["primitives"][0].erase("material");
    doc["meshes"].push_back(noMaterial);
    doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}}}},
                        {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 1, 0, 1}}}}}};
    doc["nodes"] = nlohmann::json::array();
    const std::pair<const char*, int> nodes[] = {{"", 0},       {"", 0},     {"", 1},
                                                 {"Object", 0}, {"twin", 2}, {"twin", 0}};
    for (size_t i = 0; i < std::size(nodes); ++i) {
        nlohmann::json node = {{"mesh", nodes[i].second},
                               {"translation", {double(i) - 2.5, 0.0, 0.0}}};
        if (*nodes[i].first) node["name"] = nodes[i].first;
        doc["nodes"].push_back(node);
    }
    doc["scenes"] = {{{"nodes", {0, 1, 2, 3, 4, 5}}}};
    writeJson(path("unnamed.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("unnamed.gltf") +
                         " --lookat 0,0,6,0,0,0 --fov 70 --size 96x24 -o " + path("unnamed.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    ImageBuf g(path("unnamed.exr"));
    ASSERT_TRUE(g.init_spec(path("unnamed.exr"), 0, 0));
    const OIIO::ImageSpec& spec = g.spec();

    const std::vector<std::string> objects = nameTable(spec, "dhdr:objectNames");
    const std::vector<std::string> materials = nameTable(spec, "dhdr:materialNames");
    // Index 0 of each table is the background's.
    EXPECT_EQ(objects, (std::vector<std::string>{"", "Object.001", "Object.002", "crate", "Object",
                                                 "twin", "twin.001"}));
    ASSERT_EQ(materials.size(), 4u);
    EXPECT_EQ(std::vector<std::string>(materials.begin() + 1, materials.end()),
              (std::vector<std::string>{"Material", "Material.001", "Material.002"}));

    for (const auto& [layer, table] :
         {std::pair{std::string("CryptoObject"), objects}, {"CryptoMaterial", materials}}) {
        const std::string text = manifestOf(spec, layer);
        ASSERT_FALSE(text.empty()) << layer;
        EXPECT_EQ(text.find("\"\":"), std::string::npos) << text;
        const nlohmann::json manifest = nlohmann::json::parse(text);
        // A JSON object keeps one entry per key: as many keys as names means no name twice.
        EXPECT_EQ(manifest.size(), table.size() - 1) << text;
        for (size_t i = 1; i < table.size(); ++i) {
            EXPECT_FALSE(table[i].empty()) << layer << " " << i;
            EXPECT_TRUE(manifest.contains(table[i])) << table[i] << " in " << text;
        }
    }
}

namespace {

// The square of scene_writer.h with UVs, its material (named `material`, or unnamed when
// empty) of base colour factor (0.5, 0.8, 0.6) textured by `baseColour`, emissive factor
// (2, 2, 2) textured by `emissive`, with a normal map `normal` (no texture where empty).
nlohmann::json texturedSquare(const std::string& material, const std::string& baseColour,
                              const std::string& emissive, const std::string& normal) {
    nlohmann::json doc = gltfWithMesh(squareMesh());
    const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    std::vector<std::uint8_t> bytes(sizeof uv);
    std::memcpy(bytes.data(), uv, sizeof uv);
    doc["buffers"].push_back({{"byteLength", bytes.size()},
                              {"uri", "data:application/octet-stream;base64," + base64(bytes)}});
    doc["bufferViews"].push_back({{"buffer", 1}, {"byteLength", bytes.size()}});
    doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1},
                                {"componentType", 5126},
                                {"count", 4},
                                {"type", "VEC2"}});
    doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = doc["accessors"].size() - 1;
    nlohmann::json& m = doc["materials"][0];
    if (material.empty())
        m.erase("name");
    else
        m["name"] = material;
    m["pbrMetallicRoughness"]["baseColorFactor"] = {0.5, 0.8, 0.6, 1.0};
    doc["images"] = nlohmann::json::array();
    doc["textures"] = nlohmann::json::array();
    auto texture = [&](const std::string& uri) {
        doc["images"].push_back({{"uri", uri}});
        doc["textures"].push_back({{"source", doc["images"].size() - 1}});
        return nlohmann::json{{"index", doc["textures"].size() - 1}};
    };
    if (!baseColour.empty()) m["pbrMetallicRoughness"]["baseColorTexture"] = texture(baseColour);
    if (!emissive.empty()) {
        m["emissiveTexture"] = texture(emissive);
        m["emissiveFactor"] = {2.0, 2.0, 2.0};
    }
    if (!normal.empty()) m["normalTexture"] = texture(normal);
    doc["nodes"] = {{{"name", "square"}, {"mesh", 0}}};
    doc["scenes"] = {{{"nodes", {0}}}};
    return doc;
}

} // namespace

// A missing texture aborted the whole render: now a warning naming the texture file and the
// material, and the material shows loud magenta (1, 0, 1) times its factor, as Blender shows a
// missing texture in pink (a missing normal map is left out: the surface's own normal). An
// unnamed material is named by its generated name. --strict makes it an error, with no output.
TEST_F(SceneInput, MissingTexturesAreMagentaUnlessStrict) {
    writeJson(path("missing.gltf"),
              texturedSquare("brick", "nowhere.png", "gone/glow.png", "flat_nowhere.png"));
    const std::string out = path("missing.exr");
    const Result r = run("dhdr-gbuffer " + path("missing.gltf") +
                         " --lookat 0,0,3,0,0,0 --size 16x16 -o " + out);
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string prefix = "warning: " + path("missing.gltf") + ": material 'brick', ";
    for (const auto& [slot, file, tail] :
         {std::tuple<std::string, std::string, std::string>{
              "base colour", "nowhere.png",
              "shown as magenta (1, 0, 1) times the material's factor"},
          {"emissive", "gone/glow.png", "shown as magenta (1, 0, 1) times the material's factor"},
          {"normal", "flat_nowhere.png", "the normal map is left out"}}) {
        const size_t at = r.err.find(prefix + slot + " texture: " + path(file) + ": cannot read");
        ASSERT_NE(at, std::string::npos) << slot << " in " << r.err;
        const std::string line = r.err.substr(at, r.err.find('\n', at) - at);
        EXPECT_NE(line.find(tail), std::string::npos) << line;
    }
    const ImageBuf g = read("missing.exr");
    const float* px = static_cast<const float*>(g.pixeladdr(8, 8));
    ASSERT_EQ(px[0], 1.0f);
    const int albedo = g.spec().channelindex("albedo.R");
    const int emission = g.spec().channelindex("emission.R");
    const int normal = g.spec().channelindex("N.X");
    EXPECT_NEAR(px[albedo], 0.5f, 1e-3f);
    EXPECT_NEAR(px[albedo + 1], 0.0f, 1e-3f);
    EXPECT_NEAR(px[albedo + 2], 0.6f, 1e-3f);
    EXPECT_NEAR(px[emission], 2.0f, 1e-3f);
    EXPECT_NEAR(px[emission + 1], 0.0f, 1e-3f);
    EXPECT_NEAR(px[emission + 2], 2.0f, 1e-3f);
    EXPECT_NEAR(px[normal + 2], 1.0f, 1e-3f);

    // An unnamed material: its generated name.
    writeJson(path("missing_unnamed.gltf"), texturedSquare("", "nowhere.png", "", ""));
    const Result unnamed = run("dhdr-gbuffer " + path("missing_unnamed.gltf") +
                               " --lookat 0,0,3,0,0,0 --size 8x8 -o " + path("unnamed.exr"));
    EXPECT_EQ(unnamed.status, 0) << unnamed.err;
    EXPECT_NE(unnamed.err.find("material 'Material', base colour texture: " + path("nowhere.png")),
              std::string::npos)
        << unnamed.err;

    // --strict: an error naming the file and the material, and nothing written.
    fs::remove(out);
    expectRefused(run("dhdr-gbuffer " + path("missing.gltf") +
                      " --strict --lookat 0,0,3,0,0,0 --size 16x16 -o " + out),
                  path("missing.gltf") +
                      ": material 'brick', base colour texture: " + path("nowhere.png"),
                  out);
    const Result info = run("dhdr-gbuffer " + path("missing.gltf") + " --strict --info");
    EXPECT_EQ(info.status, 1) << info.err;
    EXPECT_NE(run("dhdr-gbuffer --help").out.find("--strict"), std::string::npos);
}

// The same option wherever tools load scenes: dhdr-probes and dhdr-light (--scene,
// --camera-from) warn and go on, or with --strict refuse.
TEST_F(SceneInput, StrictAppliesWhereverScenesAreLoaded) {
    nlohmann::json doc = texturedSquare("brick", "nowhere.png", "", "");
    doc["cameras"] = {kGoodPerspective};
    doc["nodes"].push_back({{"name", "shot"}, {"camera", 0}, {"translation", {0.0, 0.0, 3.0}}});
    doc["scenes"] = {{{"nodes", {0, 1}}}};
    writeJson(path("probe_scene.gltf"), doc);
    const std::string scene = path("probe_scene.gltf");
    const std::string want =
        scene + ": material 'brick', base colour texture: " + path("nowhere.png");

    const std::string probes = "dhdr-probes " + scene + " --grid 2,2,2 --rays 16 --lights " +
                               kTestdata + "/cornell_box.lights.json -o ";
    const Result baked = run(probes + path("p.probes.exr"));
    EXPECT_EQ(baked.status, 0) << baked.err;
    EXPECT_NE(baked.err.find("warning: " + want), std::string::npos) << baked.err;
    expectRefused(run(probes + path("strict.probes.exr") + " --strict"), want,
                  path("strict.probes.exr"));

    ASSERT_EQ(run("dhdr-gbuffer " + scene + " --size 16x16 -o " + path("pg.exr")).status, 0);
    const std::string light =
        "dhdr-light " + path("pg.exr") + " --lights " + kTestdata + "/cornell_box.lights.json -o ";
    EXPECT_EQ(run(light + path("pl.exr") + " --scene " + scene).status, 0);
    expectRefused(run(light + path("strict_l.exr") + " --scene " + scene + " --strict"), want,
                  path("strict_l.exr"));
    for (const char* tool : {"dhdr-light", "dhdr-probes"})
        EXPECT_NE(run(std::string(tool) + " --help").out.find("--strict"), std::string::npos)
            << tool;
}

// A normal-mapped primitive without normals: flat normals and per-triangle tangents from its
// UVs, so the map bends N as it does on a primitive with normals (test_scene_features.cpp):
// on a square facing +Z with u along +X and v down the image, the map's (0.8, 0.5, 0.9) is
// N = (0.6, 0, 0.8) and (0.5, 0.8, 0.9) is (0, 0.6, 0.8), in both of its triangles.
TEST_F(SceneInput, FlatPrimitivesKeepTheirNormalMaps) {
    for (const auto& [name, encoded, expected] :
         std::vector<std::tuple<std::string, glm::vec3, glm::vec3>>{
             {"x", {0.8f, 0.5f, 0.9f}, {0.6f, 0.0f, 0.8f}},
             {"y", {0.5f, 0.8f, 0.9f}, {0.0f, 0.6f, 0.8f}}}) {
        ImageBuf map(OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::FLOAT));
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x)
                map.setpixel(x, y, &encoded[0]);
        ASSERT_TRUE(map.write(path("bent_" + name + ".png"), OIIO::TypeDesc::UINT8));
        nlohmann::json doc = texturedSquare("bent", "", "", "bent_" + name + ".png");
        doc["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
        writeJson(path("bent.gltf"), doc);
        const Result r = run("dhdr-gbuffer " + path("bent.gltf") +
                             " --lookat 0,0,3,0,0,0 --size 16x16 -o " + path("bent.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
        const ImageBuf g = read("bent.exr");
        const int n0 = g.spec().channelindex("N.X");
        for (const auto& [x, y] : {std::pair{5, 9}, {10, 6}}) { // one pixel in each triangle
            const float* px = static_cast<const float*>(g.pixeladdr(x, y));
            ASSERT_EQ(px[0], 1.0f);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(px[n0 + c], expected[c], 0.01f) << name << " " << x << "," << y;
        }
    }
}

// A texture whose EXR header lies (the fuzzers' 205-byte file claiming a 2 GB attribute, and a
// channel of an unknown pixel type, which aborts OpenImageIO) is a texture that cannot be
// read: the material shows magenta with a warning naming the file, nothing is allocated for
// the claim and nothing aborts.
TEST_F(SceneInput, TexturesWithLyingHeadersAreUnreadableTextures) {
    const std::string regressions = kTestdata + "/../tests/fuzz_regressions/fuzz_gbuffer/";
    for (const char* name :
         {"openexr-string-attribute-2gb.exr", "oiio-abort-unknown-pixel-type.exr"}) {
        fs::copy_file(regressions + name, path(name), fs::copy_options::overwrite_existing);
        writeJson(path("lying.gltf"), texturedSquare("brick", name, "", ""));
        const Result r = run("dhdr-gbuffer " + path("lying.gltf") +
                             " --lookat 0,0,3,0,0,0 --size 8x8 -o " + path("lying.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_NE(r.err.find(path(name) + ": cannot read texture"), std::string::npos) << r.err;
        const ImageBuf g = read("lying.exr");
        const float* px = static_cast<const float*>(g.pixeladdr(4, 4));
        EXPECT_NEAR(px[g.spec().channelindex("albedo.G")], 0.0f, 1e-3f); // magenta
    }
}
