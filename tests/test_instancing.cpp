// Rigid motion through Embree instances (issue 24): a mesh that an animation moves as a whole is
// traced as an instance of its node-space triangles, moved by its transform; it is hit where
// the posed triangles lie, within the error bounds of both, and no instanced surface shadows
// itself, far from the origin and under a transform far from a rotation, under every kernel.
#include "scene_builder.h"
#include "written_scene.h"

#include <algorithm>
#include <cmath>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/geometry/surface.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

using namespace dhdr;
using namespace dhdr::test;

namespace {

[[maybe_unused]] auto* const kKernel = ::testing::AddGlobalTestEnvironment(new EmbreeKernel);

// Three squares in a row: "still" (no animation), "rigid" (turning about Y and sliding +x,
// then flattened along its normal) and "morphed" (a position target, its weight animated).
nlohmann::json threeSquares() {
    nlohmann::json doc = squareAndCamera();
    doc["nodes"][0]["name"] = "still";
    doc["nodes"][0]["translation"] = {-1.5, 0.0, 0.0};
    doc["nodes"].push_back({{"name", "rigid"}, {"mesh", 0}});
    doc["nodes"].push_back({{"name", "morphed"}, {"mesh", 1}, {"translation", {1.5, 0.0, 0.0}}});
    doc["scenes"][0]["nodes"] = {0, 1, 2, 3};
    nlohmann::json morph = doc["meshes"][0];
    // The target's deltas: a buffer view of four vertices, +z 0.5 at each.
    const std::vector<float> deltas = {0, 0, 0.5f, 0, 0, 0.5f, 0, 0, 0.5f, 0, 0, 0.5f};
    const size_t accessor = addFloatAccessor(doc, deltas, "VEC3", 4);
    morph["primitives"][0]["targets"] = {{{"POSITION", accessor}}};
    morph["weights"] = {0.0};
    doc["meshes"].push_back(morph);
    const float s = float(std::sin(0.3)), c = float(std::cos(0.3));
    addChannel(doc, 0, 2, "rotation", {0.0f, 1.0f}, {0, 0, 0, 1, 0, s, 0, c});
    addChannel(doc, 0, 2, "translation", {0.0f, 1.0f}, {0, 0, 0, 0.25f, 0, 0});
    // Flattened along its normal by t = 2: no float matrix inverts that.
    addChannel(doc, 0, 2, "scale", {1.0f, 2.0f}, {1, 1, 1, 1, 1, 0});
    addChannel(doc, 0, 3, "weights", {0.0f, 1.0f}, {0.0f, 1.0f});
    return doc;
}

// The index of the mesh of the node named `name`'s object.
int meshNamed(const Scene& scene, const std::string& name) {
    for (size_t i = 0; i < scene.meshes.size(); ++i)
        if (scene.objectNames[size_t(scene.meshes[i].object)] == name) return int(i);
    return -1;
}

// A copy of `scene` that traces every triangle where it lies (no instances).
Scene flat(const Scene& scene) {
    Scene out = scene;
    for (Mesh& m : out.meshes)
        m.instance.reset();
    return out;
}

} // namespace

// The rigid mover is an instance; the still square and the morphed one are not (the morphed
// one's BVH is refitted). Their triangles are hit where the pose lays them: a grid of rays
// meets the same mesh and triangle as in a copy traced without instances, the points within
// both error bounds, at three moments of one caster: the instance's transform updated, then
// one that cannot be inverted (flattened), where the mesh's world-space stand-in is traced.
TEST(Instancing, RigidMoversAreInstancesHitWhereThePoseLaysThem) {
    Scene scene = load(threeSquares(), "three.gltf");
    ASSERT_TRUE(scene.rig);
    const int still = meshNamed(scene, "still"), rigid = meshNamed(scene, "rigid"),
              morphed = meshNamed(scene, "morphed");
    ASSERT_GE(still, 0);
    ASSERT_GE(rigid, 0);
    ASSERT_GE(morphed, 0);
    const std::vector<int> moving = scene.rig->movingMeshes({0});
    ScenePoser poser(scene, {0});
    poser.pose(0.4);
    EXPECT_TRUE(scene.meshes[size_t(rigid)].instance);
    EXPECT_FALSE(scene.meshes[size_t(still)].instance);
    EXPECT_FALSE(scene.meshes[size_t(morphed)].instance);
    RayCaster caster(scene, moving);
    ASSERT_TRUE(caster.ok()) << caster.error();
    EXPECT_TRUE(caster.instanced(rigid));
    EXPECT_FALSE(caster.instanced(still));
    EXPECT_FALSE(caster.instanced(morphed));

    for (const double t : {0.4, 0.9, 2.0}) {
        SCOPED_TRACE("t " + std::to_string(t));
        std::vector<int> changed;
        poser.pose(t, &changed);
        ASSERT_TRUE(caster.updateMeshes(changed));
        const Scene plain = flat(scene);
        const RayCaster reference(plain, moving);
        ASSERT_TRUE(reference.ok());
        int hits = 0, onRigid = 0, edges = 0;
        for (int j = 0; j < 60; ++j)
            for (int i = 0; i < 200; ++i) {
                // Rays from in front of the row, slanting a little, across all three squares.
                const Ray ray{glm::dvec3(-2.7 + 0.027 * i, -0.8 + 0.027 * j, 4.0),
                              glm::normalize(glm::dvec3(0.05, 0.03, -1.0))};
                const RayHit a = caster.intersect(ray), b = reference.intersect(ray);
                // Which side of an edge a ray passes is decided in the last bits (the kernel's,
                // the CPU's reciprocals): there alone may the two disagree.
                const auto onEdge = [](const RayHit& h) {
                    return std::min({h.u, h.v, 1.0f - h.u - h.v}) < 1e-5f;
                };
                if (a.hit != b.hit || a.mesh != b.mesh || a.triangle != b.triangle) {
                    EXPECT_TRUE((!a.hit || onEdge(a)) && (!b.hit || onEdge(b))) << i << "," << j;
                    ++edges;
                    continue;
                }
                if (!a.hit) continue;
                ++hits;
                onRigid += a.mesh == rigid;
                const SurfaceSample p = surfaceAt(scene, ray, a), q = surfaceAt(plain, ray, b);
                const double bound = p.positionError + q.positionError;
                for (int c = 0; c < 3; ++c)
                    ASSERT_LE(std::abs(p.position[c] - q.position[c]), bound) << c;
                // Shadow rays from just above each point towards the camera side: open in both.
                const SurfacePoint at{glm::vec3(p.position), glm::vec3(p.geometric),
                                      float(p.positionError)};
                const glm::vec3 up(0.0f, 0.0f, 1.0f);
                EXPECT_EQ(caster.transmittance(offsetRayOrigin(at, up), up, 10.0f), 1.0f);
            }
        EXPECT_GT(hits, 3000);
        EXPECT_GT(onRigid, 800);
        EXPECT_LE(edges, 3);
    }
}

// A square traced as an instance of a strip under a transform far from a rotation (squashed,
// turned off every axis, sheared), from 1 to 300 units away and up to 10⁴ from the origin:
// every pixel is lit exactly as without shadow rays under every kernel. Its points carry the
// instance's share of the bound (larger than their world triangle's alone); with no bound at
// all the same G-buffer shadows itself.
TEST(Instancing, NoInstancedSurfaceShadowsItself) {
    // A 1 × 40 strip in its node's space.
    const std::vector<glm::vec3> unit = {
        {-0.5f, -20.0f, 0.0f}, {0.5f, -20.0f, 0.0f}, {0.5f, 20.0f, 0.0f}, {-0.5f, 20.0f, 0.0f}};
    for (const double distance : {1.0, 30.0, 300.0})
        for (const double offset : {0.0, 1.0e2, 1.0e4}) {
            SCOPED_TRACE("distance " + std::to_string(distance) + ", offset " +
                         std::to_string(offset));
            const glm::dvec3 centre(offset, -0.37 * offset, 0.61 * offset);
            const glm::dvec3 axis = glm::normalize(glm::dvec3(0.31, 0.87, 0.38));
            const double size = 1.2 * distance;
            // Squashed 40:1 in the node's space, turned, then squashed 20:1 along world y: a
            // sheared parallelogram, κ∞ of its linear part about 800.
            const glm::dmat4 toWorld =
                glm::translate(glm::dmat4(1.0), centre) *
                glm::scale(glm::dmat4(1.0), glm::dvec3(1.0, 0.05, 1.0)) *
                glm::rotate(glm::dmat4(1.0), 1.1, axis) *
                glm::scale(glm::dmat4(1.0), glm::dvec3(size, size / 40.0, 1.0));
            // The square's own frame: its normal and the axes it is squashed along.
            const glm::dvec3 normal = glm::normalize(
                                 glm::dvec3(glm::transpose(glm::inverse(glm::dmat3(toWorld))) *
                                            glm::dvec3(0, 0, 1))),
                             u = glm::normalize(glm::dmat3(toWorld) * glm::dvec3(1, 0, 0));

            Scene scene = emptyScene();
            addQuad(scene, unit[0], unit[1], unit[2], unit[3]);
            auto rig = std::make_shared<SceneRig>();
            rig->meshes.resize(1);
            rig->meshes[0].node = 0;
            rig->meshes[0].positions = unit;
            rig->meshes[0].normals = scene.meshes[0].normals;
            poseMesh(rig->meshes[0], toWorld, {}, scene.meshes[0]);
            scene.meshes[0].instance = toWorld;
            scene.rig = rig;

            const glm::dvec3 eye = centre + distance * glm::normalize(normal + 0.2 * u);
            const glm::dvec3 up =
                glm::abs(normal.z) > 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
            const Camera camera = Camera::lookAt(eye, centre, up, 0.3);
            ImageBuf gbuf = gbufferOf(scene, camera, 64, 48);
            const RayCaster caster(scene);
            ASSERT_TRUE(caster.ok()) << caster.error();
            ASSERT_TRUE(caster.instanced(0));
            std::vector<Light> lights(2);
            const glm::dvec3 towards[2] = {glm::normalize(normal + 0.7 * u),
                                           glm::normalize(normal - 2.75 * u)};
            for (int i = 0; i < 2; ++i) {
                lights[size_t(i)].type = LightType::Directional;
                lights[size_t(i)].direction = glm::vec3(-towards[i]);
                lights[size_t(i)].intensity = 3.0f;
            }
            const int a = gbuf.spec().channelindex("A"),
                      e = gbuf.spec().channelindex(gbuffer::kPositionError),
                      p = gbuf.spec().channelindex("P.X");
            ASSERT_GE(e, 0);
            auto falseShadows = [&](const ImageBuf& g) {
                const ImageBuf lit = shade(g, lights, &caster), open = shade(g, lights, nullptr);
                int covered = 0, shadowed = 0;
                for (int y = 0; y < 48; ++y)
                    for (int x = 0; x < 64; ++x) {
                        if (!(px(g, x, y)[a] > 0.0f)) continue;
                        ++covered;
                        shadowed += px(lit, x, y)[0] != px(open, x, y)[0];
                    }
                EXPECT_GT(covered, 64 * 48 / 4);
                return shadowed;
            };
            EXPECT_EQ(falseShadows(gbuf), 0);

            // The instance's share is there: each point's bound exceeds its world triangle's.
            const glm::dvec3 world[3] = {glm::dvec3(scene.meshes[0].positions[0]),
                                         glm::dvec3(scene.meshes[0].positions[1]),
                                         glm::dvec3(scene.meshes[0].positions[2])};
            for (int y = 0; y < 48; ++y)
                for (int x = 0; x < 64; ++x) {
                    const float* v = px(gbuf, x, y);
                    if (!(v[a] > 0.0f)) continue;
                    EXPECT_GT(v[e], positionError(glm::dvec3(v[p], v[p + 1], v[p + 2]), world));
                }
            for (int y = 0; y < 48; ++y)
                for (int x = 0; x < 64; ++x)
                    static_cast<float*>(gbuf.pixeladdr(x, y))[e] = 0.0f;
            EXPECT_GT(falseShadows(gbuf), 0);
        }
}
