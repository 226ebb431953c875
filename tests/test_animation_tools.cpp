// dhdr-gbuffer over an animation (issue 24), as a user runs it: frames, times, the motion
// layer in Blender's Vector-pass convention, and the file's mistakes.
#include "animation_writer.h"
#include "tool_test.h"

#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/glm.hpp>

using namespace dhdr::test;
using OIIO::ImageSpec;

namespace {

class AnimationTools : public ToolTest {
protected:
    static void SetUpTestSuite() { makeScratch(); }

    // The square moving +x by 0.25 units a frame at 24 fps (6 units a second from t = 0 to 2):
    // 4 pixels a frame on the 64 × 64 orthographic image.
    static void writeSliding(const std::string& name) {
        nlohmann::json doc = squareAndCamera();
        addChannel(doc, 0, 0, "translation", {0.0f, 2.0f}, {-1, 0, 0, 11, 0, 0});
        writeJson(path(name), doc);
    }

    // Channel `name` of `img` at (x, y).
    static float value(const ImageBuf& img, const char* name, int x, int y) {
        const int c = img.spec().channelindex(name);
        EXPECT_GE(c, 0) << name;
        return c < 0 ? NAN : static_cast<const float*>(img.pixeladdr(x, y))[c];
    }
};

} // namespace

// X = Z = −v on the square's pixels (v pixels a frame towards +x), Y = W = 0; the pixels the
// square does not cover see the background of an orthographic camera: exactly 0.
TEST_F(AnimationTools, ATranslatingSquareMovesMinusVPixelsInXAndZ) {
    writeSliding("slide.gltf");
    const Result r = run("dhdr-gbuffer " + path("slide.gltf") + " --size 64x64 --frames 3-5 -o " +
                         path("slide.####.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    for (int f = 3; f <= 5; ++f) {
        char name[32];
        std::snprintf(name, sizeof name, "slide.%04d.exr", f);
        const ImageBuf g = read(name);
        ASSERT_TRUE(allFinite(g) || true);
        ASSERT_EQ(g.spec().channelformat(g.spec().channelindex("motion.X")), OIIO::TypeDesc::FLOAT);
        int covered = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                if (value(g, "A", x, y) > 0.0f) {
                    ++covered;
                    EXPECT_NEAR(value(g, "motion.X", x, y), -4.0f, 1e-4) << x << "," << y;
                    EXPECT_NEAR(value(g, "motion.Z", x, y), -4.0f, 1e-4);
                    EXPECT_EQ(value(g, "motion.Y", x, y), 0.0f);
                    EXPECT_EQ(value(g, "motion.W", x, y), 0.0f);
                } else {
                    for (const char* c : {"motion.X", "motion.Y", "motion.Z", "motion.W"})
                        EXPECT_EQ(value(g, c, x, y), 0.0f);
                }
            }
        // The square is 16 pixels wide, at x = (−1 + 0.25 f) units: 16 × 16 pixels covered.
        EXPECT_EQ(covered, 256) << f;
        // The column whose left edge is the square's centre, −1 + 0.25 f units (16 a unit).
        const float px = value(g, "P.X", 32 + int(std::lround(16 * (-1 + 0.25 * f))), 32);
        EXPECT_NEAR(px, -1.0 + 0.25 * f + 1.0 / 32, 1e-5) << f;
    }
}

// A point that does not move under a camera that does not move has a motion of exactly 0,
// in a file whose other node moves.
TEST_F(AnimationTools, WhatDoesNotMoveHasExactlyZeroMotion) {
    nlohmann::json doc = squareAndCamera();
    doc["nodes"].push_back({{"name", "other"}, {"mesh", 0}, {"translation", {-1.5, 0.0, 0.0}}});
    doc["scenes"][0]["nodes"] = {0, 1, 2};
    addChannel(doc, 0, 2, "translation", {0.0f, 1.0f}, {-1.5, 0, 0, -1.5, 1, 0});
    writeJson(path("still.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("still.gltf") + " --size 64x64 --frame 7 -o " +
                         path("still.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf g = read("still.exr");
    for (int y = 24; y < 40; ++y)
        for (int x = 24; x < 40; ++x) {
            ASSERT_GT(value(g, "A", x, y), 0.0f);
            for (const char* c : {"motion.X", "motion.Y", "motion.Z", "motion.W"})
                ASSERT_EQ(value(g, c, x, y), 0.0f) << c << " " << x << "," << y;
        }
}

// STEP: the square jumps 1 unit (16 pixels) at t = 1 s, frame 24: X = −16 there and Z = 0;
// at frame 23 X = 0 and Z = −16.
TEST_F(AnimationTools, AStepJumpsAtItsKey) {
    nlohmann::json doc = squareAndCamera();
    addChannel(doc, 0, 0, "translation", {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0}, "STEP");
    writeJson(path("step.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("step.gltf") + " --size 64x64 --frames 23-24 -o " +
                         path("step.####.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf before = read("step.0023.exr"), after = read("step.0024.exr");
    EXPECT_EQ(value(before, "motion.X", 32, 32), 0.0f);
    EXPECT_NEAR(value(before, "motion.Z", 32, 32), -16.0f, 1e-4);
    EXPECT_NEAR(value(after, "motion.X", 48, 32), -16.0f, 1e-4);
    EXPECT_EQ(value(after, "motion.Z", 48, 32), 0.0f);
    EXPECT_NEAR(value(before, "P.X", 32, 32), 1.0 / 32, 1e-6);
    EXPECT_NEAR(value(after, "P.X", 48, 32), 1.0 + 1.0 / 32, 1e-6);
}

// A camera panning (yawing 0.5° a frame) over static points: each pixel's motion is the
// reprojection of its P by the cameras of the frames before and after, computed here.
TEST_F(AnimationTools, ACameraPanMovesStaticPointsByTheirReprojection) {
    nlohmann::json doc = gltfWithMesh(squareMesh(3.0f));
    doc["cameras"] = {{{"type", "perspective"},
                       {"perspective", {{"yfov", 0.8}, {"aspectRatio", 1.5}, {"znear", 0.1}}}}};
    doc["nodes"] = {{{"name", "wall"}, {"mesh", 0}},
                    {{"name", "camera"}, {"camera", 0}, {"translation", {0.0, 0.0, 4.0}}}};
    doc["scenes"] = {{{"nodes", {0, 1}}}};
    const double perFrame = 0.5 * M_PI / 180.0; // 24 frames a second
    const double yaw1 = 24 * perFrame;
    addChannel(doc, 0, 1, "rotation", {0.0f, 1.0f},
               {0, 0, 0, 1, 0, float(std::sin(yaw1 / 2)), 0, float(std::cos(yaw1 / 2))});
    writeJson(path("pan.gltf"), doc);
    const int frame = 10, w = 96, h = 64;
    const Result r = run("dhdr-gbuffer " + path("pan.gltf") + " --size 96x64 --frame " +
                         std::to_string(frame) + " -o " + path("pan.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    const ImageBuf g = read("pan.exr");
    // A point's pixel (x right, y up) under the camera at (0, 0, 4) yawed by `yaw` about +Y.
    auto raster = [&](glm::dvec3 p, double yaw) {
        const glm::dvec3 d = p - glm::dvec3(0, 0, 4);
        const double c = std::cos(yaw), s = std::sin(yaw);
        const glm::dvec3 cam(c * d.x - s * d.z, d.y, s * d.x + c * d.z); // R(−yaw) d
        const double t = std::tan(0.4);
        return glm::dvec2((cam.x / -cam.z / (t * 1.5) + 1) * 0.5 * w,
                          (cam.y / -cam.z / t + 1) * 0.5 * h);
    };
    int checked = 0;
    for (int y = 0; y < h; y += 7)
        for (int x = 0; x < w; x += 5) {
            if (value(g, "A", x, y) == 0.0f) continue;
            const glm::dvec3 p(value(g, "P.X", x, y), value(g, "P.Y", x, y), value(g, "P.Z", x, y));
            const glm::dvec2 prev = raster(p, (frame - 1) * perFrame),
                             now = raster(p, frame * perFrame),
                             next = raster(p, (frame + 1) * perFrame);
            EXPECT_NEAR(value(g, "motion.X", x, y), prev.x - now.x, 2e-3) << x << "," << y;
            EXPECT_NEAR(value(g, "motion.Y", x, y), prev.y - now.y, 2e-3);
            EXPECT_NEAR(value(g, "motion.Z", x, y), now.x - next.x, 2e-3);
            EXPECT_NEAR(value(g, "motion.W", x, y), now.y - next.y, 2e-3);
            EXPECT_GT(std::abs(value(g, "motion.X", x, y)), 0.5f); // it does move
            ++checked;
        }
    EXPECT_GT(checked, 50);
}

// Positions at frame N equal those of a static file with frame N's transform baked into the
// node; --frame N gives the same bits as frame N of a --frames run.
TEST_F(AnimationTools, FrameNIsTheStaticSceneWithFrameNsTransforms) {
    writeSliding("bake.gltf");
    nlohmann::json baked = squareAndCamera();
    baked["nodes"][0]["translation"] = {-1.0 + 0.25 * 6, 0.0, 0.0};
    writeJson(path("baked.gltf"), baked);
    ASSERT_EQ(
        run("dhdr-gbuffer " + path("bake.gltf") + " --size 64x64 --frame 6 -o " + path("anim6.exr"))
            .status,
        0);
    ASSERT_EQ(
        run("dhdr-gbuffer " + path("baked.gltf") + " --size 64x64 -o " + path("baked.exr")).status,
        0);
    ASSERT_EQ(run("dhdr-gbuffer " + path("bake.gltf") + " --size 64x64 --frames 5-6 -o " +
                  path("seq.#.exr"))
                  .status,
              0);
    const ImageBuf a = read("anim6.exr"), b = read("baked.exr"), s = read("seq.6.exr");
    EXPECT_LT(b.spec().channelindex("motion.X"), 0); // a file without animation: no layer
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            ASSERT_EQ(value(a, "A", x, y), value(b, "A", x, y)) << x << "," << y;
            if (value(b, "A", x, y) > 0.0f) {
                for (const char* c : {"P.X", "P.Y", "P.Z", "Z"})
                    ASSERT_NEAR(value(a, c, x, y), value(b, c, x, y), 1e-6) << c;
            }
            for (int c = 0; c < a.nchannels(); ++c)
                ASSERT_EQ(static_cast<const float*>(a.pixeladdr(x, y))[c],
                          static_cast<const float*>(s.pixeladdr(x, y))[c]);
        }
}

// A node whose transform no float matrix inverts or holds still shows its mesh where the
// pose lays it (its world-space stand-in is traced, docs/animation.md): the square flattened
// along its normal covers its 16 × 16 pixels; scaled to 0 it covers none (8 × 8 half way);
// under a parent scaled by 10³⁰ over a child scaled by 10³⁰ the run goes on.
TEST_F(AnimationTools, ANodeThatNoFloatMatrixInvertsIsTracedWhereItLies) {
    struct Case {
        std::vector<float> end;
        double own;
        int half, last; // pixels covered at frames 12 and 24; −1: not checked
    };
    for (const Case& c : {Case{{1, 1, 0}, 1.0, 256, 256}, Case{{0, 0, 0}, 1.0, 64, 0},
                          Case{{1e30f, 1e30f, 1e30f}, 1e30, -1, -1}}) {
        SCOPED_TRACE(c.end[0]);
        nlohmann::json doc = squareAndCamera();
        doc["nodes"][0]["scale"] = {c.own, c.own, c.own};
        doc["nodes"].push_back({{"name", "parent"}, {"children", {0}}});
        doc["scenes"][0]["nodes"] = {1, 2};
        addChannel(doc, 0, 2, "scale", {0.0f, 1.0f}, {1, 1, 1, c.end[0], c.end[1], c.end[2]});
        writeJson(path("scaled.gltf"), doc);
        const Result r = run("dhdr-gbuffer " + path("scaled.gltf") +
                             " --size 64x64 --frames 12-24 -o " + path("scaled.#.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
        int half = 0, last = 0;
        const ImageBuf h = read("scaled.12.exr"), g = read("scaled.24.exr");
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                half += value(h, "A", x, y) > 0.0f;
                last += value(g, "A", x, y) > 0.0f;
            }
        if (c.half >= 0) {
            EXPECT_EQ(half, c.half);
        }
        if (c.last >= 0) {
            EXPECT_EQ(last, c.last);
        }
    }
}

// Frames past the last key hold its pose: the square stands still (motion 0), at x = 11.
TEST_F(AnimationTools, FramesOutsideTheAnimationHoldItsEnds) {
    writeSliding("hold.gltf");
    ASSERT_EQ(run("dhdr-gbuffer " + path("hold.gltf") + " --size 64x64 --frame 200 -o " +
                  path("late.exr") + " --lookat 11,0,5,11,0,0")
                  .status,
              0);
    const ImageBuf g = read("late.exr");
    EXPECT_GT(value(g, "A", 32, 32), 0.0f);
    EXPECT_EQ(value(g, "motion.X", 32, 32), 0.0f);
    EXPECT_EQ(value(g, "motion.Z", 32, 32), 0.0f);
    // The header says which moment it is: frame 200 at 24 fps.
    EXPECT_FLOAT_EQ(g.spec().get_float_attribute("dhdr:animationTime", -1.0f), 200.0f / 24.0f);
    EXPECT_FLOAT_EQ(g.spec().get_float_attribute("dhdr:fps", -1.0f), 24.0f);
    // A file without animation says nothing of time.
    ASSERT_EQ(run("dhdr-gbuffer " + kTestdata + "/cornell_box.gltf --size 16x16 -o " +
                  path("still_scene.exr"))
                  .status,
              0);
    EXPECT_EQ(read("still_scene.exr").spec().find_attribute("dhdr:animationTime"), nullptr);
}

// --info lists the animations with their durations; --animation picks one, and an unknown
// one is an error that lists them, with no output written.
TEST_F(AnimationTools, InfoListsAnimationsAndAnUnknownNameListsThem) {
    nlohmann::json doc = squareAndCamera();
    addChannel(doc, 0, 0, "translation", {0.0f, 2.0f}, {0, 0, 0, 1, 0, 0});
    addChannel(doc, 1, 0, "translation", {0.5f, 1.0f}, {0, 0, 0, 0, 1, 0});
    doc["animations"][1]["name"] = "bounce";
    writeJson(path("two.gltf"), doc);
    const Result info = run("dhdr-gbuffer " + path("two.gltf") + " --info");
    ASSERT_EQ(info.status, 0) << info.err;
    EXPECT_NE(info.out.find("animations  2"), std::string::npos) << info.out;
    EXPECT_NE(info.out.find("0 'anim0': 2 s (keys from 0 to 2 s), 1 channels"), std::string::npos)
        << info.out;
    EXPECT_NE(info.out.find("1 'bounce': 0.5 s (keys from 0.5 to 1 s)"), std::string::npos);
    const Result bad = run("dhdr-gbuffer " + path("two.gltf") +
                           " --size 16x16 --animation jump -o " + path("none.exr"));
    EXPECT_EQ(bad.status, 1);
    EXPECT_NE(bad.err.find("two.gltf: no animation 'jump' (the file has: 0 'anim0', 1 'bounce')"),
              std::string::npos)
        << bad.err;
    EXPECT_FALSE(fs::exists(path("none.exr")));
    EXPECT_TRUE(noTemporaries());
    // The second one moves the square up by 2 units a second: Y = −32/24 pixels a frame.
    ASSERT_EQ(run("dhdr-gbuffer " + path("two.gltf") +
                  " --size 64x64 --animation bounce --time "
                  "0.75 -o " +
                  path("bounce.exr"))
                  .status,
              0);
    // At 0.75 s the square is 0.5 units up: row 24 (0.47 units up) is on it.
    const ImageBuf g = read("bounce.exr");
    ASSERT_GT(value(g, "A", 32, 24), 0.0f);
    EXPECT_NEAR(value(g, "motion.Y", 32, 24), -16.0 * 2 / 24, 1e-4);
    EXPECT_EQ(value(g, "motion.X", 32, 24), 0.0f);
}

// A broken animation is a clear error when it is chosen: the file, the animation, the sampler
// and what is wrong; exit 1, no output. --info shows it as unusable.
TEST_F(AnimationTools, ABrokenAnimationIsAClearError) {
    nlohmann::json doc = squareAndCamera();
    addChannel(doc, 0, 0, "translation", {0.0f, 2.0f, 1.0f}, std::vector<float>(9, 0.0f));
    writeJson(path("broken.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("broken.gltf") + " --size 16x16 --frames 1-3 -o " +
                         path("broken.####.exr"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("broken.gltf: animation 'anim0' cannot be played: sampler 0: its key "
                         "times do not increase"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("broken.0001.exr")));
    const Result info = run("dhdr-gbuffer " + path("broken.gltf") + " --info");
    EXPECT_EQ(info.status, 0);
    EXPECT_NE(info.out.find("unusable: sampler 0"), std::string::npos) << info.out;
}

// The motion layer does not depend on the number of threads.
TEST_F(AnimationTools, MotionIsIndependentOfThreads) {
    writeSliding("threads.gltf");
    for (const char* n : {"1", "2", "5"})
        ASSERT_EQ(run(std::string("dhdr-gbuffer ") + path("threads.gltf") +
                      " --size 64x48 --frame 9 --threads " + n + " -o " +
                      path("t" + std::string(n) + ".exr"))
                      .status,
                  0);
    const ImageBuf a = read("t1.exr"), b = read("t2.exr"), c = read("t5.exr");
    const size_t n = a.spec().image_pixels() * size_t(a.nchannels());
    EXPECT_EQ(std::memcmp(a.localpixels(), b.localpixels(), n * 4), 0);
    EXPECT_EQ(std::memcmp(a.localpixels(), c.localpixels(), n * 4), 0);
}

// Lights on animated nodes: one lights file a frame with --lights-out PATTERN.
TEST_F(AnimationTools, LightsOutWritesOneFileAFrame) {
    nlohmann::json doc = squareAndCamera();
    doc["extensionsUsed"] = {"KHR_lights_punctual"};
    doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 5.0}}};
    doc["nodes"].push_back(
        {{"name", "lamp"}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    doc["scenes"][0]["nodes"] = {0, 1, 2};
    addChannel(doc, 0, 2, "translation", {0.0f, 1.0f}, {0, 0, 0, 24, 0, 0});
    writeJson(path("lamp.gltf"), doc);
    const Result r = run("dhdr-gbuffer " + path("lamp.gltf") + " --size 16x16 --frames 1-2 -o " +
                         path("lamp.#.exr") + " --lights-out " + path("lamp.#.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    for (int f = 1; f <= 2; ++f) {
        const auto lights =
            nlohmann::json::parse(slurp(path("lamp." + std::to_string(f) + ".json")));
        EXPECT_NE(lights.dump().find("\"position\":[" + std::to_string(f) + ".0,"),
                  std::string::npos)
            << lights.dump();
    }
}

// Deep G-buffers: every sample carries its own motion; the layer goes through dhdr-light,
// which ignores channels it does not know.
TEST_F(AnimationTools, DeepSamplesCarryMotionAndDhdrLightReadsTheFiles) {
    writeSliding("deep.gltf");
    ASSERT_EQ(run("dhdr-gbuffer " + path("deep.gltf") + " --size 64x64 --frame 4 --deep -o " +
                  path("deep.exr"))
                  .status,
              0);
    ImageBuf d(path("deep.exr"));
    ASSERT_TRUE(d.read(0, 0, true));
    ASSERT_TRUE(d.deep());
    const int mx = d.spec().channelindex("motion.X"), mz = d.spec().channelindex("motion.Z");
    ASSERT_GE(mx, 0);
    ASSERT_EQ(d.deep_samples(32, 32), 1);
    EXPECT_NEAR(d.deep_value(32, 32, 0, mx, 0), -4.0f, 1e-4);
    EXPECT_NEAR(d.deep_value(32, 32, 0, mz, 0), -4.0f, 1e-4);
    EXPECT_EQ(d.deep_samples(2, 2), 0);
    ASSERT_EQ(
        run("dhdr-gbuffer " + path("deep.gltf") + " --size 64x64 --frame 4 -o " + path("flat4.exr"))
            .status,
        0);
    for (const char* g : {"deep.exr", "flat4.exr"}) {
        const Result r = run("dhdr-light " + path(g) + " --lights " + kTestdata +
                             "/cornell_box.lights.json -o " + path(std::string("lit_") + g));
        EXPECT_EQ(r.status, 0) << g << ": " << r.err;
    }
}

// Morph motion counts: a target that shifts the square 1 unit, its weight rising 0.5 a second,
// moves it 1/48 unit (1/3 pixel) a frame: X = Z = −1/3.
// Without normals in the file, each triangle gets its own (flat, from the morphed positions).
TEST_F(AnimationTools, MorphTargetsMoveTheSurfaceAndItsMotion) {
    for (const bool normals : {true, false}) {
        nlohmann::json doc = squareAndCamera();
        if (!normals) doc["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
        addMorphTargets(doc, {{1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0}});
        addChannel(doc, 0, 0, "weights", {0.0f, 2.0f}, {0, 1}, "LINEAR", "SCALAR");
        writeJson(path("morph.gltf"), doc);
        const Result r = run("dhdr-gbuffer " + path("morph.gltf") + " --size 64x64 --frame 24 -o " +
                             path("morph.exr"));
        ASSERT_EQ(r.status, 0) << r.err;
        const ImageBuf g = read("morph.exr");
        // At t = 1 the square is shifted 0.5 units: it covers columns 32 to 47.
        EXPECT_EQ(value(g, "A", 31, 32), 0.0f);
        ASSERT_GT(value(g, "A", 40, 32), 0.0f);
        EXPECT_NEAR(value(g, "motion.X", 40, 32), -1.0 / 3.0, 1e-4);
        EXPECT_NEAR(value(g, "motion.Z", 40, 32), -1.0 / 3.0, 1e-4);
        EXPECT_NEAR(value(g, "N.Z", 40, 32), 1.0, 1e-3) << normals;
    }
}

// Assimp 5.2 crashes on a skin without inverseBindMatrices; dhdr never hands it skins. Without
// animations the mesh is rendered in its rest pose, with the warning.
TEST_F(AnimationTools, ASkinWithoutInverseBindMatricesIsNoCrash) {
    nlohmann::json doc = squareAndCamera();
    doc["nodes"].push_back({{"name", "bone"}});
    doc["scenes"][0]["nodes"] = {0, 1, 2};
    addSkin(doc, {2}, std::vector<std::uint16_t>(16, 0),
            {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    writeJson(path("skin.gltf"), doc);
    const Result r =
        run("dhdr-gbuffer " + path("skin.gltf") + " --size 16x16 -o " + path("skin.exr"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("skins are not applied"), std::string::npos) << r.err;
    EXPECT_GT(value(read("skin.exr"), "A", 8, 8), 0.0f);
    // With an animation of the bone the skin is applied, and the warning gone.
    addChannel(doc, 0, 2, "translation", {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0});
    writeJson(path("skin_anim.gltf"), doc);
    const Result a = run("dhdr-gbuffer " + path("skin_anim.gltf") + " --size 64x64 --frame 12 -o " +
                         path("skin_anim.exr"));
    ASSERT_EQ(a.status, 0) << a.err;
    EXPECT_EQ(a.err.find("skins are not applied"), std::string::npos) << a.err;
    // The bone moves the square 1/24 unit (2/3 pixel) a frame; at t = 0.5 it is 0.5 units right.
    const ImageBuf g = read("skin_anim.exr");
    ASSERT_GT(value(g, "A", 40, 32), 0.0f);
    EXPECT_EQ(value(g, "A", 23, 32), 0.0f);
    EXPECT_NEAR(value(g, "motion.X", 40, 32), -2.0 / 3.0, 1e-4);
}

// A mesh without normals (flat ones, glTF §3.7.2.1) turning about Y: frame 12 equals the static
// file with frame 12's rotation baked in, normals included.
TEST_F(AnimationTools, FlatShadedMeshesTurnWithTheirNode) {
    const double half = 15.0 * M_PI / 360.0; // 15° at t = 0.5 s, half-angle
    nlohmann::json doc = squareAndCamera();
    doc["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
    nlohmann::json baked = doc;
    baked["nodes"][0]["rotation"] = {0.0, std::sin(half), 0.0, std::cos(half)};
    // The key at t = 1: 30° about Y.
    const float s30 = float(std::sin(30.0 * M_PI / 360.0)),
                c30 = float(std::cos(30.0 * M_PI / 360.0));
    addChannel(doc, 0, 0, "rotation", {0.0f, 1.0f}, {0, 0, 0, 1, 0, s30, 0, c30});
    writeJson(path("flat_turn.gltf"), doc);
    writeJson(path("flat_baked.gltf"), baked);
    ASSERT_EQ(run("dhdr-gbuffer " + path("flat_turn.gltf") + " --size 64x64 --frame 12 -o " +
                  path("flat_turn.exr"))
                  .status,
              0);
    ASSERT_EQ(run("dhdr-gbuffer " + path("flat_baked.gltf") + " --size 64x64 -o " +
                  path("flat_baked.exr"))
                  .status,
              0);
    const ImageBuf a = read("flat_turn.exr"), b = read("flat_baked.exr");
    int covered = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            ASSERT_EQ(value(a, "A", x, y), value(b, "A", x, y)) << x << "," << y;
            if (value(b, "A", x, y) == 0.0f) continue;
            ++covered;
            for (const char* c : {"P.X", "P.Y", "P.Z"})
                ASSERT_NEAR(value(a, c, x, y), value(b, c, x, y), 1e-5) << c;
            for (const char* c : {"N.X", "N.Y", "N.Z"})
                ASSERT_NEAR(value(a, c, x, y), value(b, c, x, y), 1e-3) << c;
        }
    EXPECT_GT(covered, 200);
    EXPECT_NEAR(value(b, "N.X", 32, 32), std::sin(2 * half), 1e-3); // the baked one turned
}

// A shot's stochastic terms (soft shadows, ray-traced AO) draw per-pixel sequences that do not
// depend on the frame: where nothing moves, two frames are the same bits (no crawling noise),
// while the square that moves changes its pixels.
TEST_F(AnimationTools, WhatStaysStillIsLitTheSameInEveryFrame) {
    nlohmann::json doc = squareAndCamera();
    doc["nodes"].push_back({{"name", "mover"}, {"mesh", 0}, {"translation", {1.3, 1.3, 0.0}}});
    doc["scenes"][0]["nodes"] = {0, 1, 2};
    // 5.3 pixels a frame down the image.
    addChannel(doc, 0, 2, "translation", {0.0f, 0.5f}, {1.3, 1.3, 0, 1.3, -1.3, 0});
    writeJson(path("shot.gltf"), doc);
    std::ofstream(path("soft.lights.json"))
        << R"({"lights": [{"type": "sphere", "position": [0.5, 0.8, 2.0], "radius": 0.4,)"
           R"( "intensity": 40}]})";
    ASSERT_EQ(run("dhdr-gbuffer " + path("shot.gltf") + " --size 64x64 --frames 5-6 -o " +
                  path("shot.####.gbuf.exr"))
                  .status,
              0);
    for (int f = 5; f <= 6; ++f) {
        char in[32], out[32];
        std::snprintf(in, sizeof in, "shot.%04d.gbuf.exr", f);
        std::snprintf(out, sizeof out, "shot.%04d.hdr.exr", f);
        const Result r = run("dhdr-light --gi direct " + path(in) + " --scene " +
                             path("shot.gltf") + " --lights " + path("soft.lights.json") +
                             " --ao rt --ao-samples 8 --denoise off --type float -o " + path(out));
        ASSERT_EQ(r.status, 0) << r.err;
    }
    const ImageBuf a = read("shot.0005.hdr.exr"), b = read("shot.0006.hdr.exr");
    // The still square: pixels 24..39 (the centre unit); the mover stays right of x = 48.
    int same = 0;
    for (int y = 24; y < 40; ++y)
        for (int x = 24; x < 40; ++x)
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(a.getchannel(x, y, 0, c), b.getchannel(x, y, 0, c)) << x << "," << y;
                same += a.getchannel(x, y, 0, c) > 0.0f;
            }
    EXPECT_GT(same, 600);                                                  // lit, not black
    EXPECT_GT(OIIO::ImageBufAlgo::compare(a, b, 1e-6f, 1e-6f).nfail, 50u); // the mover moved
}
