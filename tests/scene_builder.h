// Scenes built in memory for the lighting tests (quads, boxes, a floor), and the two calls
// every such test makes: a G-buffer of the scene, and the lighting pass over it.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/deferred/core/cpu_features.h>
#include <dhdr/deferred/environment/environment.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/camera.h>
#include <dhdr/deferred/scene/scene.h>
#include <gtest/gtest.h>
#include <memory>
#include <string>
#include <vector>

namespace dhdr::test {

using OIIO::ImageBuf;

inline const float* px(const ImageBuf& img, int x, int y) {
    return static_cast<const float*>(img.pixeladdr(x, y));
}

// An environment light of radiance 1 from every direction (a 64 × 32 white image, baked).
inline Light uniformSky() {
    EnvironmentImage env;
    env.width = 64;
    env.height = 32;
    env.rgb.assign(64 * 32 * 3, 1.0f);
    auto ibl = std::make_shared<Ibl>();
    std::string error;
    EXPECT_TRUE(bakeIbl(env, IblBakeParams{}, *ibl, error)) << error;
    Light light;
    light.type = LightType::Environment;
    light.ibl = ibl;
    return light;
}

// A dim uniform sky of `sky` nits and a sun of 2×2 texels around `sun` holding about as much
// of the light, on a 128×64 image.
inline std::shared_ptr<const Ibl> skyWithSun(const glm::vec3& sun, float sky) {
    EnvironmentImage env;
    env.width = 128;
    env.height = 64;
    env.rgb.assign(size_t(128) * 64 * 3, sky);
    const glm::vec2 uv = equirectUV(sun);
    const int sx = int(uv.x * 128), sy = int(uv.y * 64);
    for (int y = sy - 1; y <= sy; ++y)
        for (int x = sx - 1; x <= sx; ++x)
            for (int c = 0; c < 3; ++c)
                env.rgb[3 * (size_t(y) * 128 + size_t(x)) + size_t(c)] = 400.0f * sky;
    auto ibl = std::make_shared<Ibl>();
    std::string error;
    EXPECT_TRUE(bakeIbl(env, IblBakeParams{}, *ibl, error)) << error;
    return ibl;
}

// A quad a b c d (counter-clockwise seen from where its normal points) as one flat mesh.
inline void addQuad(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d,
                    int material = 0) {
    Mesh m;
    m.positions = {a, b, c, d};
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    m.normals = {n, n, n, n};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.material = material;
    scene.meshes.push_back(m);
}

// An axis-aligned box as six outward-facing quads.
inline void addBox(Scene& scene, glm::vec3 lo, glm::vec3 hi, int material = 0) {
    const glm::vec3 p[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                            {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                            {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    addQuad(scene, p[0], p[3], p[2], p[1], material); // −z
    addQuad(scene, p[4], p[5], p[6], p[7], material); // +z
    addQuad(scene, p[0], p[4], p[7], p[3], material); // −x
    addQuad(scene, p[1], p[2], p[6], p[5], material); // +x
    addQuad(scene, p[0], p[1], p[5], p[4], material); // −y
    addQuad(scene, p[3], p[7], p[6], p[2], material); // +y
}

inline Scene emptyScene() {
    Scene scene;
    Material white;
    white.name = "white";
    white.baseColor = glm::vec3(0.8f);
    white.roughness = 1.0f;
    white.metallic = 0.0f;
    scene.materials.push_back(white);
    scene.objectNames = {"object"};
    return scene;
}

// The floor y = 0 over [−s, s]², facing up.
inline void addFloor(Scene& scene, float s) {
    addQuad(scene, {-s, 0, -s}, {-s, 0, s}, {s, 0, s}, {s, 0, -s});
}

inline ImageBuf gbufferOf(const Scene& scene, const Camera& camera, int w, int h) {
    ImageBuf gbuf;
    GBufferParams p;
    p.width = w;
    p.height = h;
    EXPECT_TRUE(renderGBuffer(gbuf, scene, camera, p)) << gbuf.geterror();
    return gbuf;
}

inline ImageBuf shade(const ImageBuf& gbuf, const std::vector<Light>& lights, const Visibility* vis,
                      LightingParams p = {}, int nthreads = 0, LightingStats* stats = nullptr) {
    ImageBuf out;
    EXPECT_TRUE(shadeGBuffer(out, gbuf, {lights, vis}, p, {}, nthreads, stats)) << out.geterror();
    return out;
}

// Runs the test program's tests under the Embree kernel DHDR_EMBREE_ISA names, or skips them
// all where this CPU has no such kernel (ctest runs them once for each, tests/CMakeLists.txt).
class EmbreeKernel : public ::testing::Environment {
public:
    void SetUp() override {
        const std::string isa = embreeIsaRequested();
        if (!isa.empty() && !embreeIsaSupported(isa))
            GTEST_SKIP() << "this CPU has no Embree " << isa << " kernel";
    }
};

} // namespace dhdr::test
