// What the tools say about a scene (issue 44, "Messages that say what happened"): extensions
// reported unread only when their effect is lost, --info's materials those the meshes use, a
// material that hides its surfaces named, animations dhdr cannot play said so. Each on files
// the test writes, through dhdr-gbuffer as a user meets it.
#include "scene_writer.h"
#include "tool_test.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

using namespace dhdr::test;

namespace {

class SceneMessages : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    static bool says(const Result& r, const std::string& what) {
        return r.err.find(what) != std::string::npos;
    }

    // A square as one Draco-compressed primitive (KHR_draco_mesh_compression, no uncompressed
    // fallback), its indices declared of `indexType` (5123: 16-bit, 5125: 32-bit).
    static nlohmann::json dracoSquare(int indexType) {
        const GltfMesh square = squareMesh(1.0f);
        draco::TriangleSoupMeshBuilder builder;
        builder.Start(2);
        const int position =
            builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
        for (int f = 0; f < 2; ++f) {
            const std::uint32_t* t = &square.indices[size_t(3 * f)];
            builder.SetAttributeValuesForFace(
                position, draco::FaceIndex(f), square.positions[t[0]].data(),
                square.positions[t[1]].data(), square.positions[t[2]].data());
        }
        const std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
        draco::Encoder encoder;
        draco::EncoderBuffer encoded;
        EXPECT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &encoded).ok());
        // The accessors' counts are the decoded mesh's (the encoder may merge points).
        draco::DecoderBuffer in;
        in.Init(encoded.data(), encoded.size());
        auto decoded = draco::Decoder().DecodeMeshFromBuffer(&in);
        EXPECT_TRUE(decoded.ok());
        const draco::Mesh& back = *decoded.value();
        const std::vector<std::uint8_t> bytes(encoded.data(), encoded.data() + encoded.size());

        nlohmann::json doc;
        doc["asset"] = {{"version", "2.0"}};
        doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
        doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
        doc["buffers"] = {{{"byteLength", bytes.size()},
                           {"uri", "data:application/octet-stream;base64," + base64(bytes)}}};
        doc["bufferViews"] = {{{"buffer", 0}, {"byteLength", bytes.size()}}};
        doc["accessors"] = {
            {{"componentType", 5126},
             {"count", back.num_points()},
             {"type", "VEC3"},
             {"min", {-1, -1, 0}},
             {"max", {1, 1, 0}}},
            {{"componentType", indexType}, {"count", back.num_faces() * 3}, {"type", "SCALAR"}}};
        const nlohmann::json draco = {
            {"bufferView", 0},
            {"attributes",
             {{"POSITION",
               back.GetNamedAttribute(draco::GeometryAttribute::POSITION)->unique_id()}}}};
        doc["meshes"] = {{{"name", "square"},
                          {"primitives",
                           {{{"attributes", {{"POSITION", 0}}},
                             {"indices", 1},
                             {"extensions", {{"KHR_draco_mesh_compression", draco}}}}}}}};
        doc["nodes"] = {{{"name", "square"}, {"mesh", 0}}};
        doc["scenes"] = {{{"nodes", {0}}}};
        return doc;
    }

    // The square of scene_writer.h with a second material `extra` on a second square behind it,
    // and `unused` among the file's materials with no mesh.
    static nlohmann::json twoSquares(const nlohmann::json& extra, const nlohmann::json& unused) {
        nlohmann::json doc = gltfWithMesh(squareMesh(1.0f));
        doc["materials"].push_back(extra);
        doc["materials"].push_back(unused);
        nlohmann::json second = doc["meshes"][0];
        second["name"] = "second";
        second["primitives"][0]["material"] = 1;
        doc["meshes"].push_back(second);
        doc["nodes"] = {{{"name", "front"}, {"mesh", 0}},
                        {{"name", "back"}, {"mesh", 1}, {"translation", {0.0, 0.0, -1.0}}}};
        doc["scenes"] = {{{"nodes", {0, 1}}}};
        return doc;
    }
};

} // namespace

// A Draco file renders from its compressed data (Assimp 5.2 decodes it), so the extension is
// not reported unread; an extension whose effect is lost still is. A Draco primitive whose
// 32-bit indices Assimp drops is an error that says so.
TEST_F(SceneMessages, DracoIsNotReportedUnread) {
    nlohmann::json doc = dracoSquare(5123);
    doc["extensionsUsed"].push_back("KHR_materials_iridescence");
    writeJson(path("draco.gltf"), doc);
    Result r = run("dhdr-gbuffer " + path("draco.gltf") + " --lookat 0,0,3,0,0,0 --size 16x16 -o " +
                   path("draco.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(says(r, "glTF extensions not read: KHR_materials_iridescence\n")) << r.err;
    EXPECT_FALSE(says(r, "KHR_draco_mesh_compression")) << r.err;
    // The square fills the middle of the image: its geometry came through the decoder.
    const ImageBuf g = read("draco.exr");
    EXPECT_EQ(static_cast<const float*>(g.pixeladdr(8, 8))[0], 1.0f);
    EXPECT_EQ(static_cast<const float*>(g.pixeladdr(0, 0))[0], 0.0f);

    writeJson(path("draco32.gltf"), dracoSquare(5125));
    r = run("dhdr-gbuffer " + path("draco32.gltf") + " --lookat 0,0,3,0,0,0 --size 16x16 -o " +
            path("draco32.exr"));
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(says(r, "mesh 'square' is Draco-compressed with 32-bit indices, which Assimp 5.2 "
                        "loses"))
        << r.err;
}

// --info lists the materials the meshes use, each with its factors, textures and extensions;
// neither Assimp's default material nor one no mesh uses.
TEST_F(SceneMessages, InfoListsTheMaterialsInUse) {
    const nlohmann::json glowing = {
        {"name", "glowing"},
        {"emissiveFactor", {1.0, 0.5, 0.25}},
        {"alphaMode", "BLEND"},
        {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 0.5}}}},
        {"extensions",
         {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}},
          {"KHR_materials_iridescence", {{"iridescenceFactor", 0.5}}}}}};
    writeJson(path("materials.gltf"), twoSquares(glowing, {{"name", "spare"}}));
    const Result r = run("dhdr-gbuffer " + path("materials.gltf") + " --info");
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* line :
         {"  materials   2\n",
          "    white: base colour (0.8, 0.8, 0.8), metallic 0, roughness 0.5\n",
          "    glowing: base colour (0.2, 0.4, 0.6), metallic 1, roughness 1, alpha 0.5 (blend), "
          "emission (4, 2, 1)\n",
          "      extensions: KHR_materials_emissive_strength, KHR_materials_iridescence (not "
          "read)\n"})
        EXPECT_NE(r.out.find(line), std::string::npos) << line << " in:\n" << r.out;
    EXPECT_EQ(r.out.find("spare"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("Material"), std::string::npos) << r.out;
}

// A material that hides every surface it covers is a warning naming it and its objects: an
// MTL's d 0, a glTF BLEND material of alpha 0, a MASK one whose alpha is below its cutoff.
TEST_F(SceneMessages, InvisibleMaterialsAreNamed) {
    std::ofstream(path("ghost.mtl")) << "newmtl ghost\nKd 0.5 0.5 0.5\nd 0\n";
    std::ofstream(path("ghost.obj")) << "mtllib ghost.mtl\no sheet\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\n"
                                        "usemtl ghost\nf 1 2 3\n";
    Result r = run("dhdr-gbuffer " + path("ghost.obj") + " --lookat 0,0,3,0,0,0 --size 8x8 -o " +
                   path("ghost.exr"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(says(r, "material 'ghost' has opacity 0: the surfaces that use it are invisible "
                        "(sheet)"))
        << r.err;

    const nlohmann::json clear = {{"name", "clear"},
                                  {"alphaMode", "BLEND"},
                                  {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0}}}}};
    writeJson(path("clear.gltf"), twoSquares(clear, {{"name", "spare"}}));
    r = run("dhdr-gbuffer " + path("clear.gltf") + " --info");
    EXPECT_NE(r.out.find("material 'clear' has opacity 0: the surfaces that use it are invisible "
                         "(back)"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(r.out.find("'white'"), std::string::npos) << r.out;

    const nlohmann::json cut = {{"name", "cut"},
                                {"alphaMode", "MASK"},
                                {"alphaCutoff", 0.5},
                                {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.25}}}}};
    writeJson(path("cut.gltf"), twoSquares(cut, {{"name", "spare"}}));
    r = run("dhdr-gbuffer " + path("cut.gltf") + " --info");
    EXPECT_NE(r.out.find("material 'cut' is cut out everywhere: its alpha 0.25 is below its "
                         "alphaCutoff 0.5"),
              std::string::npos)
        << r.out;
}

// A file whose animations dhdr cannot play (Collada here; FBX and glTF 1.0 the same) says so,
// and --frame and --frames on a scene that does not move warn alike.
TEST_F(SceneMessages, UnplayedAnimationsAreSaid) {
    std::ofstream(path("slide.dae")) << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><up_axis>Y_UP</up_axis></asset>
  <library_geometries><geometry id="tri"><mesh>
    <source id="pos"><float_array id="pos-array" count="9">-1 -1 0 1 -1 0 0 1 0</float_array>
      <technique_common><accessor source="#pos-array" count="3" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="vtx"><input semantic="POSITION" source="#pos"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#vtx" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_animations><animation id="slide">
    <source id="in"><float_array id="in-array" count="2">0 1</float_array>
      <technique_common><accessor source="#in-array" count="2"><param name="TIME" type="float"/>
      </accessor></technique_common></source>
    <source id="out"><float_array id="out-array" count="2">0 2</float_array>
      <technique_common><accessor source="#out-array" count="2"><param name="X" type="float"/>
      </accessor></technique_common></source>
    <sampler id="sampler"><input semantic="INPUT" source="#in"/>
      <input semantic="OUTPUT" source="#out"/></sampler>
    <channel source="#sampler" target="mover/location.X"/>
  </animation></library_animations>
  <library_visual_scenes><visual_scene id="scene">
    <node id="mover" name="mover"><translate sid="location">0 0 0</translate>
      <instance_geometry url="#tri"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
    Result r = run("dhdr-gbuffer " + path("slide.dae") +
                   " --lookat 0,0,3,0,0,0 --size 8x8 --frame 12 -o " + path("slide.exr"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(says(r, "the file's 1 animation is not played: dhdr plays glTF 2.0 animations "
                        "only"))
        << r.err;
    EXPECT_TRUE(says(r, "the scene has no animation that dhdr plays; --frame, --time and --fps "
                        "change nothing"))
        << r.err;

    writeJson(path("still.gltf"), twoSquares({{"name", "grey"}}, {{"name", "spare"}}));
    r = run("dhdr-gbuffer " + path("still.gltf") +
            " --lookat 0,0,3,0,0,0 --size 8x8 --frames 1-3 " + "-o " + path("still.####.exr"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(says(r, "still.gltf: the scene has no animation that dhdr plays; --frames writes "
                        "the same G-buffer 3 times"))
        << r.err;
    r = run("dhdr-probes " + path("still.gltf") + " --grid 2,2,2 --rays 16 --frames 1-2 -o " +
            path("probes.####.exr"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(says(r, "still.gltf: the scene has no animation that dhdr plays; --frames writes "
                        "the same probes 2 times"))
        << r.err;
    // The warning is for the frames of a still scene only.
    r = run("dhdr-gbuffer " + kTestdata + "/cornell_animated.gltf --size 8x8 --frames 1-2 -o " +
            path("moving.####.exr"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_FALSE(says(r, "no animation")) << r.err;
}
