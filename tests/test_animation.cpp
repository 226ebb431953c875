// glTF animation (issue 24): the samplers against the closed forms of the specification's
// Appendix C, the loader's node tree and ScenePoser against transforms computed here, and the
// file's mistakes as clear problems.
#include "written_scene.h"

#include <cmath>
#include <cstdlib>
#include <dhdr/deferred/scene/animation.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

using namespace dhdr;
using namespace dhdr::test;

namespace {

AnimationSampler sampler(Interpolation i, std::vector<float> times, std::vector<float> values,
                         int components, bool rotation = false) {
    AnimationSampler s;
    s.interpolation = i;
    s.times = std::move(times);
    s.values = std::move(values);
    s.components = components;
    s.rotation = rotation;
    return s;
}

double at(const AnimationSampler& s, double t, int c = 0) {
    double out[4] = {0, 0, 0, 0};
    s.evaluate(t, out);
    return out[c];
}

// The problem loading gives the file's first animation ("" when none).
std::string problemOf(const nlohmann::json& doc, const std::string& name) {
    const Scene scene = load(doc, name);
    if (!scene.rig || scene.rig->animations.empty()) return "no animation";
    return scene.rig->animations[0].problem;
}

} // namespace

TEST(AnimationSampler, LinearIsTheLineBetweenKeysAndHoldsOutside) {
    const auto s = sampler(Interpolation::Linear, {0.0f, 1.0f, 3.0f}, {0.0f, 2.0f, -2.0f}, 1);
    EXPECT_DOUBLE_EQ(at(s, 0.5), 1.0);
    EXPECT_DOUBLE_EQ(at(s, 2.0), 0.0);
    EXPECT_DOUBLE_EQ(at(s, 1.0), 2.0);
    EXPECT_DOUBLE_EQ(at(s, -1.0), 0.0); // before the first key: the first value
    EXPECT_DOUBLE_EQ(at(s, 7.0), -2.0); // after the last: the last
    EXPECT_DOUBLE_EQ(at(s, std::nan("")), 0.0);
}

TEST(AnimationSampler, StepHoldsEachKeyUntilTheNext) {
    const auto s = sampler(Interpolation::Step, {0.0f, 1.0f, 2.0f}, {5.0f, 7.0f, 9.0f}, 1);
    EXPECT_EQ(at(s, 0.999), 5.0);
    EXPECT_EQ(at(s, 1.0), 7.0);
    EXPECT_EQ(at(s, 1.5), 7.0);
    EXPECT_EQ(at(s, 2.5), 9.0);
}

// p(u) = (2u³ − 3u² + 1) v_k + td (u³ − 2u² + u) b_k + (−2u³ + 3u²) v_k+1 + td (u³ − u²) a_k+1.
TEST(AnimationSampler, CubicSplineIsHermiteWithTheTangentsScaledByTheInterval) {
    // Per key: in-tangent a, value v, out-tangent b.
    const float a0 = 9, v0 = 1, b0 = 3, a1 = -2, v1 = 4, b1 = 7;
    const auto s = sampler(Interpolation::CubicSpline, {0.5f, 2.5f}, {a0, v0, b0, a1, v1, b1}, 1);
    for (const double t : {0.5, 0.9, 1.5, 2.2, 2.5}) {
        const double td = 2.0, u = (t - 0.5) / td;
        const double expected = (2 * u * u * u - 3 * u * u + 1) * v0 +
                                td * (u * u * u - 2 * u * u + u) * b0 +
                                (-2 * u * u * u + 3 * u * u) * v1 + td * (u * u * u - u * u) * a1;
        EXPECT_NEAR(at(s, t), expected, 1e-12) << t;
    }
    EXPECT_EQ(at(s, 0.0), v0); // holds the value, not a tangent
    EXPECT_EQ(at(s, 3.0), v1);
}

// Slerp between unit quaternions along the shorter arc: halfway between no rotation and 90°
// about Z is 45° about Z, whether the second key is q or −q, and whatever the keys' length.
TEST(AnimationSampler, RotationsSlerpTheShortArcAndAreNormalised) {
    const float s45 = float(std::sin(M_PI / 4)), c45 = float(std::cos(M_PI / 4));
    for (const float sign : {1.0f, -1.0f})
        for (const float length : {1.0f, 2.0f}) {
            const auto s =
                sampler(Interpolation::Linear, {0.0f, 1.0f},
                        {0, 0, 0, length, 0, 0, sign * length * s45, sign * length * c45}, 4, true);
            for (const double u : {0.25, 0.5, 0.8}) {
                double q[4];
                s.evaluate(u, q);
                const double angle = u * M_PI / 2;
                EXPECT_NEAR(q[0], 0.0, 1e-7);
                EXPECT_NEAR(q[2], std::sin(angle / 2), 1e-7) << sign << " " << u;
                EXPECT_NEAR(q[3], std::cos(angle / 2), 1e-7) << sign << " " << u;
            }
        }
    // A cubic rotation is normalised after the Hermite sum.
    const auto cubic = sampler(
        Interpolation::CubicSpline, {0.0f, 1.0f},
        {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, s45, c45, 0, 0, 0, 0}, 4, true);
    double q[4];
    cubic.evaluate(0.5, q);
    EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-12);
}

TEST(AnimationSelection, ByNameIndexOrAllAndAnUnknownOneListsThem) {
    std::vector<Animation> animations(2);
    animations[0].name = "walk";
    animations[1].name = "run";
    std::vector<int> chosen;
    std::string error;
    ASSERT_TRUE(selectAnimations(animations, "", chosen, error));
    EXPECT_EQ(chosen, std::vector<int>{0});
    ASSERT_TRUE(selectAnimations(animations, "run", chosen, error));
    EXPECT_EQ(chosen, std::vector<int>{1});
    ASSERT_TRUE(selectAnimations(animations, "1", chosen, error));
    EXPECT_EQ(chosen, std::vector<int>{1});
    ASSERT_TRUE(selectAnimations(animations, "all", chosen, error));
    EXPECT_EQ(chosen, (std::vector<int>{0, 1}));
    EXPECT_FALSE(selectAnimations(animations, "jump", chosen, error));
    EXPECT_NE(error.find("no animation 'jump'"), std::string::npos) << error;
    EXPECT_NE(error.find("0 'walk', 1 'run'"), std::string::npos) << error;
    animations[1].problem = "sampler 0: its key times do not increase";
    EXPECT_FALSE(selectAnimations(animations, "run", chosen, error));
    EXPECT_NE(error.find("cannot be played: sampler 0"), std::string::npos) << error;
}

// The square's vertices at time t are the node's world transform at t applied to the file's
// vertices: a parent rotating about Z (slerp) and a child translating (linear) under it.
TEST(ScenePoser, MovesMeshesByTheirNodesWorldTransformAtT) {
    nlohmann::json doc = squareAndCamera();
    doc["nodes"][0] = {{"name", "parent"}, {"children", {2}}};
    doc["nodes"].push_back({{"name", "square"}, {"mesh", 0}, {"scale", {2.0, 1.0, 1.0}}});
    const float s45 = float(std::sin(M_PI / 4)), c45 = float(std::cos(M_PI / 4));
    addChannel(doc, 0, 0, "rotation", {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0, s45, c45});
    addChannel(doc, 0, 2, "translation", {0.0f, 2.0f}, {1, 0, 0, 3, 0, 0});
    Scene scene = load(doc, "hierarchy.gltf");
    ASSERT_TRUE(scene.rig);
    ASSERT_EQ(scene.rig->animations.size(), 1u);
    EXPECT_EQ(scene.rig->animations[0].problem, "");
    EXPECT_DOUBLE_EQ(scene.rig->animations[0].duration(), 2.0);
    ScenePoser poser(scene, {0});
    for (const double t : {0.0, 0.5, 1.5, 4.0}) {
        poser.pose(t);
        const double angle = std::min(t, 1.0) * M_PI / 2;
        const double x = 1.0 + std::min(t, 2.0);
        const glm::dmat4 world = glm::rotate(glm::dmat4(1.0), angle, glm::dvec3(0, 0, 1)) *
                                 glm::translate(glm::dmat4(1.0), glm::dvec3(x, 0, 0)) *
                                 glm::scale(glm::dmat4(1.0), glm::dvec3(2, 1, 1));
        const glm::dvec3 corners[4] = {
            {-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0}};
        ASSERT_EQ(scene.meshes.size(), 1u);
        for (const glm::dvec3& c : corners) {
            const glm::dvec3 expected(world * glm::dvec4(c, 1.0));
            bool found = false;
            for (const glm::vec3& p : scene.meshes[0].positions)
                found = found || glm::length(glm::dvec3(p) - expected) < 1e-5;
            EXPECT_TRUE(found) << "t " << t << " corner " << c.x << "," << c.y;
        }
        const glm::dvec3 normal = glm::normalize(glm::dmat3(world) * glm::dvec3(0, 0, 1));
        EXPECT_NEAR(glm::length(glm::dvec3(scene.meshes[0].normals[0]) - normal), 0.0, 1e-6);
    }
}

// A camera and a light on animated nodes move with them.
TEST(ScenePoser, MovesCamerasAndLights) {
    nlohmann::json doc = squareAndCamera();
    doc["extensionsUsed"] = {"KHR_lights_punctual"};
    doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 5.0}}};
    doc["nodes"].push_back({{"name", "lamp"},
                            {"translation", {0.0, 2.0, 0.0}},
                            {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    doc["scenes"][0]["nodes"] = {0, 1, 2};
    addChannel(doc, 0, 1, "translation", {0.0f, 1.0f}, {0, 0, 5, 4, 0, 5});
    addChannel(doc, 0, 2, "translation", {0.0f, 1.0f}, {0, 2, 0, 0, 2, -6});
    Scene scene = load(doc, "camera_light.gltf");
    ASSERT_EQ(scene.cameras.size(), 1u);
    ASSERT_EQ(scene.lights.size(), 1u);
    ScenePoser poser(scene, {0});
    poser.pose(0.25);
    const glm::dvec3 eye = scene.cameras[0].camera.position();
    EXPECT_NEAR(eye.x, 1.0, 1e-9);
    EXPECT_NEAR(eye.z, 5.0, 1e-9);
    EXPECT_NEAR(scene.lights[0].position.z, -1.5, 1e-6);
    EXPECT_NEAR(scene.lights[0].position.y, 2.0, 1e-6);
}

// CUBICSPLINE through the loader: Assimp 5.2 would make it linear and drop the tangents.
TEST(ScenePoser, CubicSplineTranslationFollowsHermite) {
    nlohmann::json doc = squareAndCamera();
    addChannel(doc, 0, 0, "translation", {0.0f, 1.0f},
               {0, 0, 0, 0, 0, 0, 4, 0, 0, /* key 1: */ -3, 0, 0, 1, 0, 0, 0, 0, 0}, "CUBICSPLINE");
    Scene scene = load(doc, "cubic.gltf");
    ScenePoser poser(scene, {0});
    const float x0 = scene.meshes[0].positions[0].x; // the rest pose (no translation)
    for (const double u : {0.2, 0.5, 0.7}) {
        poser.pose(u);
        const double expected = 1.0 * 4 * (u * u * u - 2 * u * u + u) +
                                (-2 * u * u * u + 3 * u * u) * 1.0 + 1.0 * (u * u * u - u * u) * -3;
        EXPECT_NEAR(scene.meshes[0].positions[0].x - x0, expected, 1e-6) << u;
    }
}

// The file's mistakes make the animation unusable, saying which sampler or channel and what;
// the scene itself still loads (its rest pose renders).
TEST(AnimationProblems, NameTheSamplerOrChannelAndWhatIsWrong) {
    const float nan = std::nanf("");
    struct Case {
        const char* name;
        std::vector<float> times, values;
        const char* path;
        int node;
        const char* expected;
    } cases[] = {
        {"decreasing",
         {0.0f, 2.0f, 1.0f},
         std::vector<float>(9, 0.0f),
         "translation",
         0,
         "sampler 0: its key times do not increase (key 2"},
        {"repeated",
         {0.0f, 1.0f, 1.0f},
         std::vector<float>(9, 0.0f),
         "translation",
         0,
         "its key times do not increase"},
        {"nan",
         {0.0f, nan},
         std::vector<float>(6, 0.0f),
         "translation",
         0,
         "sampler 0: key time 1 is not a finite number"},
        {"count",
         {0.0f, 1.0f, 2.0f},
         std::vector<float>(6, 0.0f),
         "translation",
         0,
         "has 2 output values for 3 key times: 3 expected"},
        {"nanvalue", {0.0f, 1.0f}, {0, 0, 0, nan, 0, 0}, "translation", 0, "not a finite number"},
        {"weights",
         {0.0f, 1.0f},
         {0.0f, 1.0f},
         "weights",
         0,
         "weights of a node whose mesh has no morph targets"},
        {"node",
         {0.0f, 1.0f},
         std::vector<float>(6, 0.0f),
         "translation",
         7,
         "channel 0: its target node 7 does not exist"},
        {"path",
         {0.0f, 1.0f},
         std::vector<float>(6, 0.0f),
         "colour",
         0,
         "channel 0: its target path 'colour'"},
    };
    for (const Case& c : cases) {
        nlohmann::json doc = squareAndCamera();
        addChannel(doc, 0, c.node, c.path, c.times, c.values, "LINEAR",
                   std::string(c.path) == "weights" ? "SCALAR" : "VEC3");
        const std::string problem = problemOf(doc, std::string(c.name) + ".gltf");
        EXPECT_NE(problem.find(c.expected), std::string::npos) << c.name << ": " << problem;
    }
    // An animated node given by a matrix.
    nlohmann::json doc = squareAndCamera();
    doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    addChannel(doc, 0, 0, "translation", {0.0f, 1.0f}, std::vector<float>(6, 0.0f));
    EXPECT_NE(problemOf(doc, "matrix.gltf").find("is given by a matrix"), std::string::npos);
}

// Morph targets from the file: vertex = base + Σ wᵢ Δᵢ (a negative weight included, which
// Assimp 5.2 clamps), morphed before the node's transform; CUBICSPLINE weights of two targets
// (three values per key per target, which Assimp 5.2 miscounts).
TEST(ScenePoser, MorphTargetsAreBasePlusWeightedDeltas) {
    const std::vector<float> shift = {1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0};
    const std::vector<float> spread = {0, 0, 0, 0, 0.5f, 0, 0, 1, 0, 0, 1.5f, 0};
    for (const char* interpolation : {"LINEAR", "CUBICSPLINE"}) {
        nlohmann::json doc = squareAndCamera();
        doc["nodes"][0]["translation"] = {0.0, 0.0, -1.0};
        addMorphTargets(doc, {shift, spread}, {0.2f, 0.0f});
        const bool cubic = std::string(interpolation) == "CUBICSPLINE";
        // Weights (0, 0) at t = 0 to (1, −0.5) at t = 1; cubic: tangents (in, out) per key.
        const std::vector<float> values =
            cubic ? std::vector<float>{0, 0, 0, 0, 3, -1, -2, 1, 1, -0.5f, 0, 0}
                  : std::vector<float>{0, 0, 1, -0.5f};
        addChannel(doc, 0, 0, "weights", {0.0f, 1.0f}, values, interpolation, "SCALAR");
        Scene scene = load(doc, std::string("morph_") + interpolation + ".gltf");
        ASSERT_TRUE(scene.rig);
        ASSERT_EQ(scene.rig->animations[0].problem, "") << interpolation;
        const float base[4][3] = {
            {-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}};
        // Loaded with the default weights (0.2, 0).
        for (int v = 0; v < 4; ++v)
            EXPECT_NEAR(scene.meshes[0].positions[size_t(v)].x, base[v][0] + 0.2, 1e-6);
        ScenePoser poser(scene, {0});
        for (const double u : {0.3, 0.5, 2.0}) {
            poser.pose(u);
            const double t = std::min(u, 1.0);
            double w[2] = {t, -0.5 * t};
            if (cubic) {
                const double h10 = t * t * t - 2 * t * t + t, h01 = -2 * t * t * t + 3 * t * t,
                             h11 = t * t * t - t * t;
                // v0 = (0, 0), b0 = (3, −1), v1 = (1, −0.5), a1 = (−2, 1); td = 1.
                w[0] = h10 * 3 + h01 * 1 + h11 * -2;
                w[1] = h10 * -1 + h01 * -0.5 + h11 * 1;
            }
            for (int v = 0; v < 4; ++v) {
                const glm::vec3 p = scene.meshes[0].positions[size_t(v)];
                EXPECT_NEAR(p.x, base[v][0] + w[0] * shift[size_t(3 * v)], 1e-6) << interpolation;
                EXPECT_NEAR(p.y, base[v][1] + w[1] * spread[size_t(3 * v + 1)], 1e-6)
                    << interpolation;
                EXPECT_NEAR(p.z, -1.0, 1e-6);
            }
        }
    }
    // Weights of the wrong count for the mesh's two targets.
    nlohmann::json doc = squareAndCamera();
    addMorphTargets(doc, {shift, spread});
    addChannel(doc, 0, 0, "weights", {0.0f, 1.0f}, {0, 0, 1}, "LINEAR", "SCALAR");
    EXPECT_NE(problemOf(doc, "morph_count.gltf")
                  .find("has 3 weights for 2 keys of 2 morph targets: 4 expected"),
              std::string::npos);
}

// A two-joint skin against matrices computed here: vertex = Σ wₖ world(jointₖ)
// inverseBind(jointₖ) v, the skinned node's own transform ignored; a skin without
// inverseBindMatrices has identity ones (Assimp 5.2 crashes on it: it never sees the skin).
TEST(ScenePoser, TwoJointSkinFollowsItsJointMatrices) {
    for (const bool inverseBind : {true, false}) {
        nlohmann::json doc = squareAndCamera();
        doc["nodes"][0]["translation"] = {5.0, 0.0, 0.0}; // ignored: the mesh is skinned
        doc["nodes"].push_back({{"name", "hip"}, {"children", {3}}});
        doc["nodes"].push_back({{"name", "knee"}, {"translation", {0.0, 0.5, 0.0}}});
        doc["scenes"][0]["nodes"] = {0, 1, 2};
        // Vertices 0 and 1 on the hip; 2 and 3 three quarters on the knee, a quarter on the hip.
        addSkin(doc, {2, 3}, {0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0},
                {1, 0, 0, 0, 1, 0, 0, 0, 0.75f, 0.25f, 0, 0, 0.75f, 0.25f, 0, 0},
                inverseBind ? std::vector<float>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0,     0, 1,
                                                 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -0.5f, 0, 1}
                            : std::vector<float>{});
        const float s45 = float(std::sin(M_PI / 4)), c45 = float(std::cos(M_PI / 4));
        addChannel(doc, 0, 2, "rotation", {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0, s45, c45});
        addChannel(doc, 0, 3, "translation", {0.0f, 1.0f}, {0, 0.5f, 0, 1, 0.5f, 0});
        Scene scene = load(doc, inverseBind ? "skin.gltf" : "skin_no_ibm.gltf");
        ASSERT_TRUE(scene.rig);
        ASSERT_EQ(scene.rig->skins.size(), 1u);
        const glm::dmat4 ibm1 =
            inverseBind ? glm::translate(glm::dmat4(1.0), glm::dvec3(0, -0.5, 0)) : glm::dmat4(1.0);
        const glm::dvec3 base[4] = {{-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0}};
        ScenePoser poser(scene, {0});
        for (const double t : {0.0, 0.4, 1.0}) {
            poser.pose(t);
            const glm::dmat4 hip = glm::rotate(glm::dmat4(1.0), t * M_PI / 2, glm::dvec3(0, 0, 1));
            const glm::dmat4 knee = hip * glm::translate(glm::dmat4(1.0), glm::dvec3(t, 0.5, 0));
            const glm::dmat4 j0 = hip, j1 = knee * ibm1;
            for (int v = 0; v < 4; ++v) {
                const glm::dmat4 m = v < 2 ? j0 : 0.75 * j1 + 0.25 * j0;
                const glm::dvec3 expected(m * glm::dvec4(base[v], 1.0));
                const glm::dvec3 got(scene.meshes[0].positions[size_t(v)]);
                EXPECT_NEAR(glm::length(got - expected), 0.0, 1e-6)
                    << "ibm " << inverseBind << " t " << t << " vertex " << v;
            }
        }
    }
    // A joint that is not a node is an error naming the file and the skin.
    nlohmann::json doc = squareAndCamera();
    addSkin(doc, {9}, std::vector<std::uint16_t>(16, 0), std::vector<float>(16, 0.25f));
    addChannel(doc, 0, 0, "translation", {0.0f, 1.0f}, std::vector<float>(6, 0.0f));
    writeJson(scratch("bad_joint.gltf"), doc);
    Scene scene;
    std::string error;
    EXPECT_FALSE(loadScene(scratch("bad_joint.gltf"), scene, error));
    EXPECT_NE(error.find("bad_joint.gltf: skin 0: joint 9 is not a node"), std::string::npos)
        << error;
}

// A node naming a skin the file does not have, and JOINTS_0 naming a joint past the skin's.
TEST(AnimationProblems, ABadSkinReferenceIsAnError) {
    for (const bool missingSkin : {true, false}) {
        nlohmann::json doc = squareAndCamera();
        addSkin(doc, {0}, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 3},
                std::vector<float>(16, 0.25f));
        if (missingSkin) doc["nodes"][0]["skin"] = 5;
        addChannel(doc, 0, 0, "translation", {0.0f, 1.0f}, std::vector<float>(6, 0.0f));
        writeJson(scratch("bad_skin.gltf"), doc);
        Scene scene;
        std::string error;
        EXPECT_FALSE(loadScene(scratch("bad_skin.gltf"), scene, error));
        EXPECT_NE(error.find(missingSkin ? "node 0, primitive 0 (morph targets or skin): its "
                                           "node's skin 5 does not exist"
                                         : "JOINTS_0 names joint 3 of a skin of 1 joints"),
                  std::string::npos)
            << error;
    }
}

// An accessor claiming more elements than its buffer holds, or billions of zeros, is refused
// before anything is allocated.
TEST(AnimationProblems, AccessorsLargerThanTheirBuffersAreRefused) {
    for (const bool view : {true, false}) {
        nlohmann::json doc = squareAndCamera();
        addChannel(doc, 0, 0, "translation", {0.0f, 1.0f}, std::vector<float>(6, 0.0f));
        const size_t output = doc["animations"][0]["samplers"][0]["output"];
        doc["accessors"][output]["count"] = 4000000000u;
        if (!view) doc["accessors"][output].erase("bufferView");
        const std::string problem = problemOf(doc, view ? "big_view.gltf" : "big_zeros.gltf");
        EXPECT_NE(problem.find(view ? "elements run past bufferView" : "more than dhdr reads"),
                  std::string::npos)
            << problem;
    }
}
