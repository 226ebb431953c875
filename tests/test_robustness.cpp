// Other people's files and careless command lines, as issue 8 found them: each test runs the
// tools as a user would and fails on the defect it is named after.
#include "scene_writer.h"
#include "tool_test.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <csignal>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/tonemap/bloom.h>
#include <dhdr/tonemap/edge_aa.h>
#include <map>
#include <set>
#include <thread>
#include <unistd.h>

using namespace dhdr::test;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

const std::string kCornell = kTestdata + "/cornell_box.gltf";
const std::string kLights = kTestdata + "/cornell_box.lights.json";

class Robustness : public ToolTest {
protected:
    static void SetUpTestSuite() {
        makeScratch();
        sharedInputs([] {
            ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 64x64 -o " + path("g.exr")).status,
                      0);
            ASSERT_EQ(run("dhdr-light " + path("g.exr") + " --lights " + kLights +
                          " --type float -o " + path("h.exr"))
                          .status,
                      0);
        });
    }

    // Float pixels of `spec`'s size and channels (whatever its type), pixel (x, y) channel c
    // being f(x, y, c).
    template <class F>
    static ImageBuf makeImage(ImageSpec spec, F f) {
        spec.set_format(TypeDesc::FLOAT);
        spec.channelformats.clear();
        ImageBuf img(spec);
        for (int y = 0; y < spec.height; ++y)
            for (int x = 0; x < spec.width; ++x)
                for (int c = 0; c < spec.nchannels; ++c)
                    static_cast<float*>(img.pixeladdr(x, y))[c] = f(x, y, c);
        return img;
    }

    // An object (a bright square) on a transparent background: R=G=B=v inside, A=1.
    static ImageBuf objectOnEmpty(float v) {
        ImageSpec spec(64, 64, 4, TypeDesc::FLOAT);
        spec.channelnames = {"R", "G", "B", "A"};
        spec.alpha_channel = 3;
        return makeImage(spec, [v](int x, int y, int c) {
            const bool inside = x >= 24 && x < 40 && y >= 24 && y < 40;
            return inside ? (c == 3 ? 1.0f : v * (1.0f + 0.1f * float(c))) : 0.0f;
        });
    }

    static std::vector<std::uint32_t> readUintChannel(const std::string& file,
                                                      const char* channel) {
        Imf::InputFile in(file.c_str());
        const Imath::Box2i dw = in.header().dataWindow();
        const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        std::vector<std::uint32_t> ids(size_t(w) * size_t(h));
        Imf::FrameBuffer fb;
        fb.insert(channel, Imf::Slice(Imf::UINT,
                                      reinterpret_cast<char*>(ids.data() - dw.min.x - dw.min.y * w),
                                      sizeof(std::uint32_t), sizeof(std::uint32_t) * size_t(w)));
        in.setFrameBuffer(fb);
        in.readPixels(dw.min.y, dw.max.y);
        return ids;
    }

    static bool equalPixels(const ImageBuf& a, const ImageBuf& b, int chbegin, int chend) {
        if (a.roi() != b.roi()) return false;
        for (int y = a.roi().ybegin; y < a.roi().yend; ++y)
            for (int x = a.roi().xbegin; x < a.roi().xend; ++x)
                for (int c = chbegin; c < chend; ++c)
                    if (static_cast<const float*>(a.pixeladdr(x, y))[c] !=
                        static_cast<const float*>(b.pixeladdr(x, y))[c])
                        return false;
        return true;
    }
};

} // namespace

// 1. Object and material ids, read back as uint by OpenEXR itself, against the scene's own
// ray casts: the id of the mesh each pixel's primary ray hits.
TEST_F(Robustness, IdsAreTheSceneObjectsReadAsUint) {
    const std::vector<std::uint32_t> objects = readUintChannel(path("g.exr"), "id.object");
    const std::vector<std::uint32_t> materials = readUintChannel(path("g.exr"), "id.material");
    dhdr::Scene scene;
    std::string error;
    ASSERT_TRUE(dhdr::loadScene(kCornell, scene, error)) << error;
    const dhdr::RayCaster caster(scene);
    ASSERT_TRUE(caster.ok());
    const ImageBuf g = read("g.exr");
    dhdr::Camera camera = scene.cameras[0].camera;
    std::set<std::uint32_t> seen;
    int agree = 0, total = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const dhdr::RayHit hit = caster.intersect(camera.primaryRay(x, y, 64, 64));
            const size_t i = size_t(y * 64 + x);
            const std::uint32_t object =
                hit.hit ? std::uint32_t(scene.meshes[size_t(hit.mesh)].object + 1) : 0;
            const std::uint32_t material =
                hit.hit ? std::uint32_t(scene.meshes[size_t(hit.mesh)].material + 1) : 0;
            ++total;
            agree += objects[i] == object && materials[i] == material;
            seen.insert(objects[i]);
        }
    EXPECT_EQ(agree, total);
    // Every object of the box is in view, each under its own id, and the background is 0.
    std::set<std::uint32_t> all = {0};
    for (size_t k = 1; k <= scene.objectNames.size(); ++k)
        all.insert(std::uint32_t(k));
    EXPECT_EQ(seen, all);
    // The name table maps them back.
    const OIIO::ParamValue* names = g.spec().find_attribute("dhdr:objectNames");
    ASSERT_NE(names, nullptr);
    const auto* table = static_cast<const OIIO::ustring*>(names->data());
    for (size_t k = 0; k < scene.objectNames.size(); ++k)
        EXPECT_EQ(table[k + 1].string(), scene.objectNames[k]);
}

// 2. A Blender multilayer render: channels sorted by name, AO before Combined.
TEST_F(Robustness, LayeredExrIsReadByName) {
    ImageSpec spec(64, 64, 0, TypeDesc::FLOAT);
    spec.channelnames = {"ViewLayer.AO.B",       "ViewLayer.AO.G",       "ViewLayer.AO.R",
                         "ViewLayer.Combined.A", "ViewLayer.Combined.B", "ViewLayer.Combined.G",
                         "ViewLayer.Combined.R", "ViewLayer.Normal.X",   "ViewLayer.Normal.Y",
                         "ViewLayer.Normal.Z"};
    spec.nchannels = int(spec.channelnames.size());
    spec.alpha_channel = -1;
    const ImageBuf object = objectOnEmpty(40.0f);
    const ImageBuf layered = makeImage(spec, [&](int x, int y, int c) {
        const float* p = static_cast<const float*>(object.pixeladdr(x, y));
        if (c < 3) return 0.3f + 0.01f * float(x); // AO
        if (c == 3) return p[3];
        if (c < 7) return p[6 - c]; // B, G, R
        return c == 9 ? 1.0f : 0.0f;
    });
    ASSERT_TRUE(layered.write(path("blender.exr")));
    ASSERT_TRUE(object.write(path("combined.exr")));

    // dhdr-tonemap maps Combined, with Combined.A as alpha: as the plain file.
    ASSERT_EQ(run("dhdr-tonemap " + path("blender.exr") + " -o " + path("blender.png")).status, 0);
    ASSERT_EQ(run("dhdr-tonemap " + path("combined.exr") + " -o " + path("combined.png")).status,
              0);
    const ImageBuf a = read("blender.png"), b = read("combined.png");
    ASSERT_EQ(a.nchannels(), 4);
    EXPECT_TRUE(equalPixels(a, b, 0, 4));

    // dhdr-bloom blooms Combined and passes AO and Normal through bit for bit.
    Result r = run("dhdr-bloom " + path("blender.exr") + " --threshold 0.1 -o " +
                   path("blender_bloom.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    ASSERT_EQ(run("dhdr-bloom " + path("combined.exr") + " --threshold 0.1 -o " +
                  path("combined_bloom.exr"))
                  .status,
              0);
    const ImageBuf bloomed = read("blender_bloom.exr"), plain = read("combined_bloom.exr");
    ASSERT_EQ(bloomed.nchannels(), 10);
    const ImageBuf in = read("blender.exr");
    for (const char* name : {"ViewLayer.AO.R", "ViewLayer.Normal.Z", "ViewLayer.Combined.A"}) {
        const int c = bloomed.spec().channelindex(name), k = in.spec().channelindex(name);
        ASSERT_GE(c, 0) << name;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x)
                ASSERT_EQ(static_cast<const float*>(bloomed.pixeladdr(x, y))[c],
                          static_cast<const float*>(in.pixeladdr(x, y))[k])
                    << name;
    }
    const int red = bloomed.spec().channelindex("ViewLayer.Combined.R");
    float changed = 0.0f;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const float v = static_cast<const float*>(bloomed.pixeladdr(x, y))[red];
            EXPECT_EQ(v, static_cast<const float*>(plain.pixeladdr(x, y))[0]);
            changed =
                std::max(changed, std::abs(v - static_cast<const float*>(in.pixeladdr(x, y))[6]));
        }
    EXPECT_GT(changed, 0.0f); // it did bloom

    // dhdr-aa filters Combined only, as it filters the plain file.
    r = run("dhdr-aa " + path("blender.exr") + " --gbuffer " + path("g.exr") + " -o " +
            path("blender_aa.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    ASSERT_EQ(run("dhdr-aa " + path("combined.exr") + " --gbuffer " + path("g.exr") + " -o " +
                  path("combined_aa.exr"))
                  .status,
              0);
    const ImageBuf aa = read("blender_aa.exr"), aaPlain = read("combined_aa.exr");
    for (int c = 0; c < 10; ++c) {
        const std::string& name = in.spec().channelnames[size_t(c)];
        const int k = aa.spec().channelindex(name);
        ASSERT_GE(k, 0) << name;
        const bool combined = name.find("Combined") != std::string::npos;
        const int plainChannel = std::string("RGBA").find(name.back());
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x)
                ASSERT_EQ(static_cast<const float*>(aa.pixeladdr(x, y))[k],
                          combined
                              ? static_cast<const float*>(aaPlain.pixeladdr(x, y))[plainChannel]
                              : static_cast<const float*>(in.pixeladdr(x, y))[c])
                    << name << " at " << x << "," << y;
    }

    // --layer chooses another; an unknown one lists what there is.
    ASSERT_EQ(
        run("dhdr-tonemap " + path("blender.exr") + " --layer AO -o " + path("ao.png")).status, 0);
    EXPECT_FALSE(equalPixels(read("ao.png"), b, 0, 3));
    r = run("dhdr-tonemap " + path("blender.exr") + " --layer Diffuse -o " + path("x.png"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("no colour layer or part 'Diffuse'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("ViewLayer.AO"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("x.png")));

    // Two layers and no convention: an error that lists them.
    ImageSpec two(8, 8, 6, TypeDesc::HALF);
    two.channelnames = {"diffuse.B",  "diffuse.G",  "diffuse.R",
                        "specular.B", "specular.G", "specular.R"};
    ASSERT_TRUE(
        makeImage(two, [](int, int, int) { return 1.0f; }).write(path("two.exr"), TypeDesc::HALF));
    for (const char* tool : {"dhdr-tonemap", "dhdr-bloom", "dhdr-aa"}) {
        r = run(std::string(tool) + " " + path("two.exr") + " -o " + path("two_out.exr"));
        EXPECT_EQ(r.status, 1) << tool;
        EXPECT_NE(r.err.find("cannot tell which layer"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("diffuse, specular"), std::string::npos) << r.err;
    }
}

// 2. A multi-part EXR: the part named beauty, not part 0; --layer names a part.
TEST_F(Robustness, MultiPartExrFindsThePartByName) {
    ImageSpec ao(32, 32, 3, TypeDesc::HALF), beauty(32, 32, 4, TypeDesc::HALF);
    ao.attribute("oiio:subimagename", "AO");
    beauty.attribute("oiio:subimagename", "beauty");
    beauty.alpha_channel = 3;
    const ImageBuf aoPixels = makeImage(ao, [](int, int, int) { return 0.25f; });
    const ImageBuf beautyPixels =
        makeImage(beauty, [](int x, int, int c) { return c == 3 ? 1.0f : 0.05f * float(x + c); });
    {
        auto out = OIIO::ImageOutput::create(path("parts.exr"));
        const ImageSpec specs[2] = {ao, beauty};
        ASSERT_TRUE(out->open(path("parts.exr"), 2, specs));
        ASSERT_TRUE(aoPixels.write(out.get()));
        ASSERT_TRUE(out->open(path("parts.exr"), beauty, OIIO::ImageOutput::AppendSubimage));
        ASSERT_TRUE(beautyPixels.write(out.get()));
        ASSERT_TRUE(out->close());
    }
    ASSERT_TRUE(beautyPixels.write(path("beauty.exr"), TypeDesc::HALF));
    ASSERT_EQ(run("dhdr-tonemap " + path("parts.exr") + " -o " + path("parts.png")).status, 0);
    ASSERT_EQ(run("dhdr-tonemap " + path("beauty.exr") + " -o " + path("beauty.png")).status, 0);
    EXPECT_TRUE(equalPixels(read("parts.png"), read("beauty.png"), 0, 4));
    ASSERT_EQ(run("dhdr-bloom " + path("parts.exr") + " --layer AO -o " + path("ao.exr")).status,
              0);
    const ImageBuf bloomedAO = read("ao.exr");
    EXPECT_EQ(bloomedAO.nchannels(), 3);
}

// 3. An orthographic glTF camera, and --fov outside [0, 180) (0: the camera's own).
TEST_F(Robustness, OrthographicCamera) {
    nlohmann::json doc = gltfWithMesh(squareMesh(1.0f));
    doc["cameras"] = {
        {{"type", "orthographic"},
         {"orthographic", {{"xmag", 1.5}, {"ymag", 1.5}, {"znear", 0.1}, {"zfar", 100}}}}};
    // Looking down −Z from z = 5, the square tilted so that depth varies across it.
    doc["nodes"] = {{{"name", "square"}, {"mesh", 0}, {"rotation", {0.0, 0.258819, 0.0, 0.965926}}},
                    {{"name", "ortho"}, {"camera", 0}, {"translation", {0.0, 0.0, 5.0}}}};
    doc["scenes"] = {{{"nodes", {0, 1}}}};
    doc["scene"] = 0;
    writeJson(path("ortho.gltf"), doc);
    Result r = run("dhdr-gbuffer " + path("ortho.gltf") + " --size 60x60 -o " + path("ortho.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf g = read("ortho.exr");
    EXPECT_EQ(g.spec().get_string_attribute("dhdr:projection"), "orthographic");
    const int px = g.spec().channelindex("P.X"), py = g.spec().channelindex("P.Y");
    // Pixel centres 3/60 apart on a 3 × 3 image plane, whatever the depth.
    for (int y = 10; y < 50; y += 7)
        for (int x = 20; x < 40; x += 5) {
            const float* p = static_cast<const float*>(g.pixeladdr(x, y));
            ASSERT_EQ(p[0], 1.0f) << x << "," << y; // covered
            EXPECT_NEAR(p[px], -1.5 + (x + 0.5) * 0.05, 1e-5);
            EXPECT_NEAR(p[py], 1.5 - (y + 0.5) * 0.05, 1e-5);
        }
    const OIIO::ParamValue* m = g.spec().find_attribute("worldToNDC", OIIO::TypeMatrix44);
    ASSERT_NE(m, nullptr);
    const float* f = static_cast<const float*>(m->data());
    for (int i = 0; i < 16; ++i)
        ASSERT_TRUE(std::isfinite(f[i]));
    // Lit: culled equals brute force, and the view vector is the camera's axis everywhere.
    std::ofstream(path("ortho.lights.json"))
        << R"({"lights": [{"type": "point", "position": [0.3, 0.2, 1.0], "intensity": 2, "range": 3},
                         {"type": "spot", "position": [-0.5, 0.0, 2.0], "direction": [0, 0, -1],
                          "intensity": 5, "range": 4}]})";
    for (const char* mode : {"", " --brute-force"})
        ASSERT_EQ(run("dhdr-light " + path("ortho.exr") + " --lights " + path("ortho.lights.json") +
                      " --type float" + mode + " -o " + path(*mode ? "lb.exr" : "lc.exr"))
                      .status,
                  0);
    const ImageBuf culled = read("lc.exr"), brute = read("lb.exr");
    ASSERT_TRUE(culled.initialized() && brute.initialized());
    EXPECT_TRUE(allFinite(culled));
    double worst = 0.0, energy = 0.0;
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 60; ++x)
            for (int c = 0; c < 3; ++c) {
                const float a = static_cast<const float*>(culled.pixeladdr(x, y))[c];
                const float b = static_cast<const float*>(brute.pixeladdr(x, y))[c];
                worst = std::max(worst, double(std::abs(a - b)));
                energy += b;
            }
    EXPECT_LT(worst, 1e-5);
    EXPECT_GT(energy, 0.0);
    for (const char* fov : {"180", "-5", "-0.001", "nan"}) {
        r = run("dhdr-gbuffer " + kCornell + " --fov " + fov + " -o " + path("fov.exr"));
        EXPECT_EQ(r.status, 2) << fov;
        EXPECT_NE(r.err.find("--fov"), std::string::npos) << r.err;
    }
}

// 4. An object on an empty background: metered without the background, nothing in it passes
// the threshold, so bloom adds nothing, as it adds nothing on a grey background.
TEST_F(Robustness, BloomMetersWithoutTheTransparentBackground) {
    ASSERT_TRUE(objectOnEmpty(1.0f).write(path("object.exr")));
    Result r = run("dhdr-bloom " + path("object.exr") + " -o " + path("object_bloom.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(equalPixels(read("object.exr"), read("object_bloom.exr"), 0, 4));
}

// 5. A camera that sees nothing: every stage says so, and still succeeds.
TEST_F(Robustness, EmptyFramesAreReported) {
    Result r = run("dhdr-gbuffer " + kCornell + " --lookat 0,0,-5,0,0,-10 --size 32x24 -o " +
                   path("empty.gbuf.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("no surface in view"), std::string::npos) << r.err;
    r = run("dhdr-light " + path("empty.gbuf.exr") + " --lights " + kLights + " -o " +
            path("empty.hdr.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("empty.gbuf.exr: no surface in view"), std::string::npos) << r.err;
    for (const std::string& c :
         {"dhdr-aa " + path("empty.hdr.exr") + " --gbuffer " + path("empty.gbuf.exr") + " -o " +
              path("empty.aa.exr"),
          "dhdr-bloom " + path("empty.hdr.exr") + " -o " + path("empty.bloom.exr"),
          "dhdr-tonemap " + path("empty.hdr.exr") + " -o " + path("empty.png")}) {
        r = run(c);
        EXPECT_EQ(r.status, 0) << c << r.err;
        EXPECT_NE(r.err.find("empty.hdr.exr: no surface in view"), std::string::npos) << r.err;
    }
}

// 6. Radiance past half's range: clamped to 65504 and counted, never +Inf.
TEST_F(Robustness, HalfOutputIsClampedNotInfinite) {
    std::ofstream(path("blinding.json"))
        << R"({"lights": [{"type": "point", "position": [0.278, 0.274, 0.28], "intensity": 1e9}]})";
    Result r = run("dhdr-light " + path("g.exr") + " --lights " + path("blinding.json") + " -o " +
                   path("blinding.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("clamped"), std::string::npos) << r.err;
    const ImageBuf hdr = read("blinding.exr");
    EXPECT_EQ(hdr.nativespec().format, TypeDesc::HALF);
    EXPECT_TRUE(allFinite(hdr));
    float largest = 0.0f;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            largest = std::max(largest, static_cast<const float*>(hdr.pixeladdr(x, y))[0]);
    EXPECT_EQ(largest, 65504.0f);
    // Float keeps them.
    r = run("dhdr-light " + path("g.exr") + " --lights " + path("blinding.json") +
            " --type float -o " + path("blinding_f.exr"));
    ASSERT_EQ(r.status, 0);
    EXPECT_EQ(r.err.find("clamped"), std::string::npos) << r.err;
}

// 7. Zero-length normals in the file: the triangle's geometric normal, and a warning.
TEST_F(Robustness, ZeroNormalsBecomeGeometricNormals) {
    GltfMesh mesh = squareMesh(1.0f);
    mesh.normals.assign(4, {0.0f, 0.0f, 0.0f});
    nlohmann::json doc = gltfWithMesh(mesh);
    // The square turned 90° about X: its geometric normal is −Y... seen from below, +Y up.
    doc["nodes"] = {
        {{"name", "square"}, {"mesh", 0}, {"rotation", {0.7071068, 0.0, 0.0, 0.7071068}}}};
    doc["scenes"] = {{{"nodes", {0}}}};
    writeJson(path("zero_normals.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("zero_normals.gltf") +
                         " --lookat 0.2,3,0.1,0,0,0 --size 16x16 -o " + path("zn.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("zero length"), std::string::npos) << r.err;
    const ImageBuf g = read("zn.exr");
    const int n = g.spec().channelindex("N.X");
    const float* p = static_cast<const float*>(g.pixeladdr(8, 8));
    ASSERT_EQ(p[0], 1.0f);
    // Rotating +Z by 90° about X gives −Y; facing the camera above, +Y.
    EXPECT_NEAR(p[n], 0.0f, 1e-3);
    EXPECT_NEAR(p[n + 1], 1.0f, 1e-3);
    EXPECT_NEAR(p[n + 2], 0.0f, 1e-3);
}

// 8. Half input stays half.
TEST_F(Robustness, BloomAndAAKeepTheInputTypes) {
    ImageBuf half = objectOnEmpty(3.0f);
    ImageBuf converted = half.copy(TypeDesc::HALF);
    ASSERT_TRUE(converted.write(path("half.exr"), TypeDesc::HALF));
    ASSERT_EQ(run("dhdr-bloom " + path("half.exr") + " -o " + path("half_bloom.exr")).status, 0);
    EXPECT_EQ(read("half_bloom.exr").nativespec().format, TypeDesc::HALF);
    const Result r = run("dhdr-aa " + path("half.exr") + " --gbuffer " + path("g.exr") + " -o " +
                         path("half_aa.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(read("half_aa.exr").nativespec().format, TypeDesc::HALF);
}

// 9. A camera looking straight down, and one whose eye is its target.
TEST_F(Robustness, TopDownCameraRendersAndEyeAtTargetIsAUsageError) {
    Result r = run("dhdr-gbuffer " + kCornell +
                   " --lookat 0.278,5,0.28,0.278,0,0.28 --size 32x32 -o " + path("top.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf top = read("top.exr");
    // Looking down on the box: the floor and blocks fill the middle of the picture.
    EXPECT_EQ(static_cast<const float*>(top.pixeladdr(16, 16))[0], 1.0f);
    r = run("dhdr-gbuffer " + kCornell + " --lookat 1,1,1,1,1,1 -o " + path("same.exr"));
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("same point"), std::string::npos) << r.err;
    EXPECT_TRUE(noTemporaries());
}

// 10. A tiled input: scanline output, the same pixels as from the scanline file.
TEST_F(Robustness, TiledInputGivesScanlineOutput) {
    ImageBuf hdr = read("h.exr");
    hdr.set_write_tiles(16, 16);
    ASSERT_TRUE(hdr.write(path("tiled.exr")));
    {
        auto in = OIIO::ImageInput::open(path("tiled.exr"));
        ASSERT_EQ(in->spec().tile_width, 16);
    }
    for (const std::string& tool : {std::string("dhdr-bloom"), "dhdr-aa --gbuffer " + path("g.exr"),
                                    std::string("dhdr-tonemap")}) {
        const std::string name = tool.substr(5, 2);
        Result r = run(tool + " " + path("tiled.exr") + " -o " + path(name + "_tiled.exr"));
        ASSERT_EQ(r.status, 0) << tool << ": " << r.err;
        ASSERT_EQ(run(tool + " " + path("h.exr") + " -o " + path(name + "_scan.exr")).status, 0);
        EXPECT_EQ(read(name + "_tiled.exr").nativespec().tile_width, 0);
        EXPECT_TRUE(equalPixels(read(name + "_tiled.exr"), read(name + "_scan.exr"), 0, 4)) << tool;
    }
    ImageBuf g = read("g.exr");
    g.set_write_tiles(32, 32);
    ASSERT_TRUE(g.write(path("g_tiled.exr")));
    const Result r =
        run("dhdr-light " + path("g_tiled.exr") + " --lights " + kLights + " -o " + path("lt.exr"));
    EXPECT_EQ(r.status, 0) << r.err;
}

// 11. dhdr-aa streams strips with a halo of rows: its output equals edge AA of the whole frame
// bit for bit, with taps reaching 3 pixels across strip boundaries.
TEST_F(Robustness, EdgeAAStripsEqualTheWholeFrame) {
    ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 90x150 -o " + path("tall.gbuf.exr")).status,
              0);
    ASSERT_EQ(run("dhdr-light " + path("tall.gbuf.exr") + " --lights " + kLights +
                  " --type float -o " + path("tall.hdr.exr"))
                  .status,
              0);
    const Result r = run("dhdr-aa " + path("tall.hdr.exr") + " --gbuffer " + path("tall.gbuf.exr") +
                         " --max-offset 3 -o " + path("tall.aa.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf hdr = read("tall.hdr.exr"), g = read("tall.gbuf.exr");
    const int n = g.spec().channelindex("N.X"), z = g.spec().channelindex("Z");
    const int normalChannels[3] = {n, n + 1, n + 2}, depthChannel[1] = {z};
    const ImageBuf normal = OIIO::ImageBufAlgo::channels(g, 3, normalChannels);
    const ImageBuf depth = OIIO::ImageBufAlgo::channels(g, 1, depthChannel);
    dhdr::EdgeAAParams params;
    params.maxOffset = 3.0f;
    ImageBuf whole = hdr.copy(TypeDesc::FLOAT);
    OIIO::ROI colour = hdr.roi();
    colour.chend = 4;
    ASSERT_TRUE(dhdr::edgeAA(whole, hdr, &normal, &depth, params, colour));
    const ImageBuf streamed = read("tall.aa.exr");
    EXPECT_TRUE(equalPixels(streamed, whole, 0, 4));
    EXPECT_FALSE(equalPixels(streamed, hdr, 0, 4)); // it did filter
}

// 11. dhdr-bloom streams the frame twice, strip by strip: its output equals bloom() of the
// whole frame bit for bit.
TEST_F(Robustness, BloomStripsEqualTheWholeFrame) {
    ASSERT_EQ(run("dhdr-gbuffer " + kCornell + " --size 100x170 -o " + path("b.gbuf.exr")).status,
              0);
    ASSERT_EQ(run("dhdr-light " + path("b.gbuf.exr") + " --lights " + kLights +
                  " --type float -o " + path("b.hdr.exr"))
                  .status,
              0);
    const Result r =
        run("dhdr-bloom " + path("b.hdr.exr") + " --threshold 0.3 -o " + path("b.bloom.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf hdr = read("b.hdr.exr");
    dhdr::BloomParams params;
    params.threshold = 0.3f;
    ImageBuf whole;
    ASSERT_TRUE(dhdr::bloom(whole, hdr, params));
    const ImageBuf streamed = read("b.bloom.exr");
    EXPECT_TRUE(equalPixels(streamed, whole, 0, 4));
    EXPECT_FALSE(equalPixels(streamed, hdr, 0, 3)); // it did bloom
}

// 2. A G-buffer in the second part of a multi-part EXR (a render's beauty first): dhdr-light
// and dhdr-aa --gbuffer find it by its channels, and light and filter as with the plain file.
TEST_F(Robustness, GBufferInASecondPartIsFound) {
    const ImageBuf g = read("g.exr"), h = read("h.exr");
    ImageSpec beautySpec = h.spec(), gSpec = g.spec();
    beautySpec.attribute("oiio:subimagename", "beauty");
    gSpec.attribute("oiio:subimagename", "gbuffer");
    {
        auto out = OIIO::ImageOutput::create(path("gparts.exr"));
        const ImageSpec specs[2] = {beautySpec, gSpec};
        ASSERT_TRUE(out->open(path("gparts.exr"), 2, specs));
        ASSERT_TRUE(h.write(out.get()));
        ASSERT_TRUE(out->open(path("gparts.exr"), gSpec, OIIO::ImageOutput::AppendSubimage));
        ASSERT_TRUE(g.write(out.get()));
        ASSERT_TRUE(out->close());
    }
    // The plain G-buffer as the parts file holds it: float, read back by OIIO.
    ASSERT_TRUE(g.write(path("g_float.exr")));
    for (const std::string& gb : {std::string("gparts.exr"), std::string("g_float.exr")}) {
        Result r = run("dhdr-light " + path(gb) + " --lights " + kLights + " --type float -o " +
                       path("lit_" + gb));
        ASSERT_EQ(r.status, 0) << r.err;
        r = run("dhdr-aa " + path("h.exr") + " --gbuffer " + path(gb) + " -o " + path("aa_" + gb));
        ASSERT_EQ(r.status, 0) << r.err;
    }
    EXPECT_TRUE(equalPixels(read("lit_gparts.exr"), read("lit_g_float.exr"), 0, 4));
    EXPECT_TRUE(equalPixels(read("aa_gparts.exr"), read("aa_g_float.exr"), 0, 4));
}
