// The reference path tracer (--gi path) against independent answers: a white furnace, one
// bounce between a lit wall and a floor against a quadrature of the same two BRDFs, and the
// deferred direct pass where both compute the same thing.
#include "scene_builder.h"

#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/lights/emissive_lights.h>
#include <dhdr/deferred/scene/scene.h>
#include <glm/gtc/type_ptr.hpp>
#include <gtest/gtest.h>
#include <map>

using namespace dhdr;
using namespace dhdr::test;

namespace {

ImageBuf pathTraced(const ImageBuf& gbuf, const std::vector<Light>& lights, const RayCaster& caster,
                    int samples, int bounces, int nthreads = 0) {
    LightingParams p;
    p.pathTrace = true;
    p.pathSamples = samples;
    p.pathBounces = bounces;
    LightingInputs inputs{lights, &caster};
    inputs.scene = &caster;
    ImageBuf out;
    EXPECT_TRUE(shadeGBuffer(out, gbuf, inputs, p, {}, nthreads)) << out.geterror();
    return out;
}

glm::vec3 positionOf(const ImageBuf& gbuf, int x, int y) {
    const OIIO::ImageSpec& s = gbuf.spec();
    return {px(gbuf, x, y)[s.channelindex("P.X")], px(gbuf, x, y)[s.channelindex("P.Y")],
            px(gbuf, x, y)[s.channelindex("P.Z")]};
}

bool covered(const ImageBuf& gbuf, int x, int y) {
    return px(gbuf, x, y)[gbuf.spec().channelindex("A")] > 0.0f;
}

// A 2 × 2 × 2 room (white floor, ceiling and back wall, a red left and a green right wall, and
// with `closed` a white front wall) around a 0.6 × 0.9 × 0.6 box of `metal`.
Scene metalBoxInARoom(const glm::vec3& metalColour, float roughness, bool closed) {
    Scene scene = emptyScene();
    Material red = scene.materials[0], green = red, metal = red;
    red.baseColor = glm::vec3(0.7f, 0.05f, 0.05f);
    green.baseColor = glm::vec3(0.1f, 0.6f, 0.1f);
    metal.baseColor = metalColour;
    metal.metallic = 1.0f;
    metal.roughness = roughness;
    scene.materials.insert(scene.materials.end(), {red, green, metal});
    const float s = 1.0f;
    addQuad(scene, {-s, 0, -s}, {-s, 0, s}, {s, 0, s}, {s, 0, -s});                 // floor
    addQuad(scene, {-s, 2 * s, -s}, {s, 2 * s, -s}, {s, 2 * s, s}, {-s, 2 * s, s}); // ceiling
    addQuad(scene, {-s, 0, -s}, {s, 0, -s}, {s, 2 * s, -s}, {-s, 2 * s, -s});       // back
    addQuad(scene, {-s, 0, -s}, {-s, 2 * s, -s}, {-s, 2 * s, s}, {-s, 0, s}, 1);    // left, red
    addQuad(scene, {s, 0, -s}, {s, 0, s}, {s, 2 * s, s}, {s, 2 * s, -s}, 2);        // right, green
    if (closed) addQuad(scene, {-s, 0, s}, {-s, 2 * s, s}, {s, 2 * s, s}, {s, 0, s}); // front
    const size_t before = scene.meshes.size();
    addBox(scene, {-0.3f, 0.0f, -0.3f}, {0.3f, 0.9f, 0.3f});
    for (size_t m = before; m < scene.meshes.size(); ++m)
        scene.meshes[m].material = 3;
    return scene;
}

// The room's camera, and its light: a point light under the ceiling.
const Camera kRoomCamera = Camera::lookAt({0.3, 1.0, 0.95}, {0.0, 0.45, 0.0}, {0, 1, 0}, 1.1);

Light roomLight() {
    Light light;
    light.type = LightType::Point;
    light.position = glm::vec3(0.2f, 1.8f, 0.4f);
    light.intensity = 2.0f;
    light.range = 20.0f;
    return light;
}

// The means of `a` and `b` over the pixels of the box (x, z within 0.3, y up to 0.9, and above
// `floorY`), and how many.
int boxMeans(const ImageBuf& gbuf, int W, int H, const ImageBuf& a, const ImageBuf& b,
             glm::dvec3& meanA, glm::dvec3& meanB, float top = 0.901f, float floorY = -1.0f) {
    meanA = meanB = glm::dvec3(0.0);
    int n = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const glm::vec3 P = positionOf(gbuf, x, y);
            if (!covered(gbuf, x, y) || std::abs(P.x) > 0.301f || std::abs(P.z) > 0.301f ||
                P.y > top || P.y < floorY)
                continue;
            meanA += glm::dvec3(glm::make_vec3(px(a, x, y)));
            meanB += glm::dvec3(glm::make_vec3(px(b, x, y)));
            ++n;
        }
    if (n > 0) meanA /= double(n), meanB /= double(n);
    return n;
}

// Probes baked for `lights` at `spacing` (the bake's defaults otherwise).
ProbeVolume bakedProbes(const Scene& scene, const RayCaster& caster,
                        const std::vector<Light>& lights, double spacing) {
    ProbeBakeParams bake;
    bake.spacing = spacing;
    ProbeVolume probes;
    std::string error;
    EXPECT_TRUE(bakeProbes(scene, caster, lights, true, bake, probes, error)) << error;
    return probes;
}

// The frame of the deferred pass with `probes` (none: direct light only) and no traced specular
// light: the probes' indirect light is this frame less the one without them.
ImageBuf deferredFrame(const ImageBuf& gbuf, const std::vector<Light>& lights,
                       const RayCaster& caster, const ProbeVolume* probes) {
    LightingParams p;
    p.specularSamples = 0;
    LightingInputs inputs{lights, &caster};
    inputs.scene = &caster;
    inputs.probes = probes;
    ImageBuf out;
    EXPECT_TRUE(shadeGBuffer(out, gbuf, inputs, p)) << out.geterror();
    return out;
}

// A surface's indirect light, summed over its pixels per channel: the probes' and the path
// tracer's (each frame less the direct-only frame), and Σ (half − path)², half the path tracer
// at half its paths (the first half of the same paths): (half − full)² estimates the variance
// of a pixel's full mean without bias (Var(half − other half) / 4), so the square root of the
// sum over n pixels, over n, is the standard error of the surface's mean.
struct IndirectSums {
    glm::dvec3 probes{0.0}, path{0.0}, squares{0.0};
    int pixels = 0;
    glm::dvec3 probesMean() const { return probes / double(pixels); }
    glm::dvec3 pathMean() const { return path / double(pixels); }
    glm::dvec3 standardError() const { return glm::sqrt(squares) / double(pixels); }
};

// IndirectSums per surface, the surface of a covered pixel named by `surfaceOf` (-1: none);
// `half` may be null (no standard error).
template <class SurfaceOf>
std::map<int, IndirectSums> indirectPerSurface(const ImageBuf& gbuf, const ImageBuf& direct,
                                               const ImageBuf& withProbes, const ImageBuf& path,
                                               const ImageBuf* half, SurfaceOf surfaceOf) {
    std::map<int, IndirectSums> sums;
    const OIIO::ROI roi = gbuf.roi();
    for (int y = roi.ybegin; y < roi.yend; ++y)
        for (int x = roi.xbegin; x < roi.xend; ++x) {
            if (!covered(gbuf, x, y)) continue;
            const int surface = surfaceOf(x, y);
            if (surface < 0) continue;
            const glm::dvec3 d(glm::make_vec3(px(direct, x, y))),
                full(glm::make_vec3(px(path, x, y)));
            IndirectSums& s = sums[surface];
            s.probes += glm::dvec3(glm::make_vec3(px(withProbes, x, y))) - d;
            s.path += full - d;
            if (half) {
                const glm::dvec3 e = glm::dvec3(glm::make_vec3(px(*half, x, y))) - full;
                s.squares += e * e;
            }
            ++s.pixels;
        }
    return sums;
}

// Rec. 709 luminance of a mean (linear: the mean of the pixels' luminances).
double luminanceOf(const glm::dvec3& c) {
    return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

} // namespace

// A white furnace: every surface a white metal (F0 = 1, whose reflectance with multiple
// scattering is 1 within 1.2 %, MultipleScattering tests) under a sky of radiance 1, in a
// concave arrangement (a box on a floor before a wall) where paths bounce many times. Every
// pixel sees radiance 1, whatever the geometry: at 1024 paths a pixel the mean within 1 %
// (measured 1.001) and every pixel within 0.2 (the noise: measured 0.10 at worst, 0.36 at 64
// paths).
TEST(PathTracer, WhiteFurnaceIsOneEverywhere) {
    Scene scene = emptyScene();
    scene.materials[0].baseColor = glm::vec3(1.0f);
    scene.materials[0].metallic = 1.0f;
    scene.materials[0].roughness = 0.6f;
    addFloor(scene, 2.0f);
    addBox(scene, {-0.4f, 0.0f, -0.4f}, {0.4f, 0.8f, 0.4f});
    addQuad(scene, {-2, 0, -1}, {2, 0, -1}, {2, 2, -1}, {-2, 2, -1}); // a wall facing +z
    const Camera camera = Camera::lookAt({0.5, 1.2, 2.5}, {0.0, 0.4, 0.0}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(scene, camera, 48, 36);
    const RayCaster caster(scene);
    const ImageBuf lit = pathTraced(gbuf, {uniformSky()}, caster, 1024, 32);
    double sum = 0.0, worst = 0.0;
    int n = 0;
    for (int y = 0; y < 36; ++y)
        for (int x = 0; x < 48; ++x) {
            if (!covered(gbuf, x, y)) continue;
            for (int c = 0; c < 3; ++c) {
                sum += px(lit, x, y)[c];
                worst = std::max(worst, double(std::abs(px(lit, x, y)[c] - 1.0f)));
                ++n;
            }
        }
    std::printf("white furnace: mean %.4f, worst pixel off by %.4f\n", sum / n, worst);
    EXPECT_GT(n, 3 * 1000);
    EXPECT_NEAR(sum / n, 1.0, 0.01);
    EXPECT_LT(worst, 0.2);
}

// The same furnace with every surface clearcoated (KHR_materials_clearcoat, weight 1,
// roughness 0.1): (1 − b) · 1 + b · 1 is still 1, but only if the coat's lobe, sampled as a
// third technique, is weighed by the density it was drawn with (the mean within 1 %).
TEST(PathTracer, WhiteFurnaceUnderAClearcoatIsOne) {
    Scene scene = emptyScene();
    scene.materials[0].baseColor = glm::vec3(1.0f);
    scene.materials[0].metallic = 1.0f;
    scene.materials[0].roughness = 0.6f;
    scene.materials[0].clearcoat = 1.0f;
    scene.materials[0].clearcoatRoughness = 0.1f;
    addFloor(scene, 2.0f);
    addBox(scene, {-0.4f, 0.0f, -0.4f}, {0.4f, 0.8f, 0.4f});
    const Camera camera = Camera::lookAt({0.5, 1.2, 2.5}, {0.0, 0.4, 0.0}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(scene, camera, 32, 24);
    ASSERT_GE(gbuf.spec().channelindex("clearcoat"), 0);
    const RayCaster caster(scene);
    const ImageBuf lit = pathTraced(gbuf, {uniformSky()}, caster, 256, 16);
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x)
            if (covered(gbuf, x, y))
                for (int c = 0; c < 3; ++c, ++n)
                    sum += px(lit, x, y)[c];
    std::printf("coated white furnace: mean %.4f\n", sum / n);
    EXPECT_GT(n, 3 * 300);
    EXPECT_NEAR(sum / n, 1.0, 0.01);
}

// The furnace once more with a white sheen over the white metal (KHR_materials_sheen, colour
// 1, roughness 0.5): the base keeps 1 − E_sheen(N·V) and the sheen lobe reflects E_sheen(N·V),
// so every bounce still returns all it receives (the mean within 1 %).
TEST(PathTracer, WhiteFurnaceUnderASheenIsOne) {
    Scene scene = emptyScene();
    scene.materials[0].baseColor = glm::vec3(1.0f);
    scene.materials[0].metallic = 1.0f;
    scene.materials[0].roughness = 0.6f;
    scene.materials[0].sheenColor = glm::vec3(1.0f);
    scene.materials[0].sheenRoughness = 0.5f;
    addFloor(scene, 2.0f);
    addBox(scene, {-0.4f, 0.0f, -0.4f}, {0.4f, 0.8f, 0.4f});
    const Camera camera = Camera::lookAt({0.5, 1.2, 2.5}, {0.0, 0.4, 0.0}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(scene, camera, 32, 24);
    ASSERT_GE(gbuf.spec().channelindex("sheenRoughness"), 0);
    const RayCaster caster(scene);
    const ImageBuf lit = pathTraced(gbuf, {uniformSky()}, caster, 256, 16);
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x)
            if (covered(gbuf, x, y))
                for (int c = 0; c < 3; ++c, ++n)
                    sum += px(lit, x, y)[c];
    std::printf("sheened white furnace: mean %.4f\n", sum / n);
    EXPECT_GT(n, 3 * 300);
    EXPECT_NEAR(sum / n, 1.0, 0.01);
}

// One bounce: a wall at x = d (2 × 4 m, facing −x) lit head-on by a sun travelling +x, which
// grazes the floor and lights it not at all. A floor point's radiance towards the camera is
// then ∫_wall f_floor(V, ω) L_wall(−ω) cos θ dω with L_wall(−ω) = f_wall(−ω, −sun) E: a
// quadrature of that integral over the floor point's hemisphere (512 × 1024 cells, in
// double, the wall intersected analytically) against 4096 paths of one bounce: the mean
// relative error over 64 pixels within 1 % (measured −0.3 %), its RMS within 4 % (the
// paths' noise, about 2.5 % a pixel).
TEST(PathTracer, OneBounceBetweenAWallAndTheFloorMatchesAQuadrature) {
    const float d = 0.6f, H = 2.0f, W = 2.0f;
    Scene scene = emptyScene();
    addFloor(scene, 2.0f);
    addQuad(scene, {d, 0, -W}, {d, 0, W}, {d, H, W}, {d, H, -W}); // facing −x
    const glm::dvec3 eye(0.0, 3.0, 0.5);
    const Camera camera = Camera::lookAt(eye, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.25);
    const ImageBuf gbuf = gbufferOf(scene, camera, 8, 8);
    const RayCaster caster(scene);
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::vec3(1.0f, 0.0f, 0.0f);
    const ImageBuf lit = pathTraced(gbuf, {sun}, caster, 4096, 1);
    PbrSurface white;
    white.baseColor = glm::vec3(0.8f);
    const glm::vec3 up(0.0f, 1.0f, 0.0f), wallNormal(-1.0f, 0.0f, 0.0f), toSun(-1.0f, 0.0f, 0.0f);
    double sumRelative = 0.0, sumSquares = 0.0;
    int n = 0;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            ASSERT_TRUE(covered(gbuf, x, y));
            const glm::vec3 P = positionOf(gbuf, x, y);
            const glm::vec3 V = glm::normalize(glm::vec3(eye) - P);
            // 512 × 1024 cells: against 1024 × 2048 the 64 pixels' values differ by 0.17 % at
            // most and 0.013 % in the mean, a tenth of the paths' noise and of the mean's
            // margin, at a quarter of the cost (the quadrature was most of the test's time).
            constexpr int kTheta = 512, kPhi = 1024;
            double expected = 0.0;
            for (int i = 0; i < kTheta; ++i) {
                const double theta = (i + 0.5) / kTheta * (kPi / 2.0);
                const double dOmega = std::sin(theta) * (kPi / 2.0 / kTheta) * (2.0 * kPi / kPhi);
                for (int j = 0; j < kPhi; ++j) {
                    const double phi = (j + 0.5) / kPhi * 2.0 * kPi;
                    const glm::dvec3 w(std::sin(theta) * std::cos(phi), std::cos(theta),
                                       std::sin(theta) * std::sin(phi));
                    if (!(w.x > 0.0)) continue;
                    const double t = (d - P.x) / w.x, hy = t * w.y, hz = P.z + t * w.z;
                    if (!(hy < H) || !(std::abs(hz) < W)) continue;
                    const glm::vec3 wi(w);
                    const double wall = luminance(evaluateBrdf(white, wallNormal, -wi, toSun));
                    const double floor = luminance(evaluateBrdf(white, up, V, wi));
                    expected += floor * wall * std::cos(theta) * dOmega;
                }
            }
            const double got =
                luminance(glm::vec3(px(lit, x, y)[0], px(lit, x, y)[1], px(lit, x, y)[2]));
            const double relative = got / expected - 1.0;
            sumRelative += relative;
            sumSquares += relative * relative;
            ++n;
        }
    const double rms = std::sqrt(sumSquares / n);
    std::printf("one bounce against the quadrature: mean %+.4f, RMS %.4f\n", sumRelative / n, rms);
    EXPECT_LT(std::abs(sumRelative / n), 0.01);
    EXPECT_LT(rms, 0.04);
}

// With no bounce, the path tracer and the deferred pass compute the same direct light of
// point, spot and directional lights with their shadows (the same shadow rays): equal within
// float rounding on every pixel. Bit for bit across thread counts.
TEST(PathTracer, WithoutBouncesItIsTheDirectPassForDeltaLights) {
    Scene scene = emptyScene();
    scene.materials[0].roughness = 0.4f;
    Material red = scene.materials[0];
    red.baseColor = glm::vec3(0.8f, 0.1f, 0.1f);
    red.metallic = 1.0f;
    scene.materials.push_back(red);
    addFloor(scene, 2.0f);
    addBox(scene, {-0.3f, 0.0f, -0.3f}, {0.3f, 0.6f, 0.3f});
    scene.meshes.back().material = 1;
    const Camera camera = Camera::lookAt({0.8, 1.5, 2.0}, {0.0, 0.3, 0.0}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(scene, camera, 64, 48);
    const RayCaster caster(scene);
    std::vector<Light> lights(3);
    lights[0].type = LightType::Point;
    lights[0].position = glm::vec3(0.6f, 1.2f, 0.4f);
    lights[0].range = 10.0f;
    lights[1].type = LightType::Spot;
    lights[1].position = glm::vec3(-0.8f, 1.0f, 0.5f);
    lights[1].direction = glm::normalize(glm::vec3(0.8f, -1.0f, -0.5f));
    lights[1].range = 10.0f;
    lights[1].innerConeAngle = 0.3f;
    lights[1].outerConeAngle = 0.6f;
    lights[2].type = LightType::Directional;
    lights[2].direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.4f));
    lights[2].intensity = 0.5f;
    const ImageBuf direct = shade(gbuf, lights, &caster);
    const ImageBuf path = pathTraced(gbuf, lights, caster, 1, 0, 1);
    const ImageBuf path2 = pathTraced(gbuf, lights, caster, 1, 0, 2);
    int lit = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 4; ++c) {
                const float a = px(direct, x, y)[c], b = px(path, x, y)[c];
                ASSERT_NEAR(a, b, 1e-5f + 1e-5f * std::abs(a)) << x << "," << y << " " << c;
                ASSERT_EQ(b, px(path2, x, y)[c]);
                lit += c == 0 && a > 0.0f;
            }
    EXPECT_GT(lit, 1500);
}

// With no bounce, the path tracer's light samples and BRDF samples (MIS) against the deferred
// pass's closed forms, both at many samples, over rough surfaces: area lights (a sphere and a
// rectangle; analytic, times their ray-traced visibility) with a box's shadows, and a sky
// (prefiltered) over the floor alone. The frames' mean luminance within 1 % (measured +0.03 %
// and −0.11 %; the sky was +4.4 % before the diffuse layer's Fresnel transmission,
// multiple_scattering.h), the RMS of the difference per pixel within 3 % of the mean. (With
// the box the deferred sky is brighter by design: its specular visibility counts a grey
// occluder's light for the blocked directions, docs/ibl.md, which a path of no bounce does
// not see.) And the sky through a Blend sheet, which paths pass by its coverage.
TEST(PathTracer, WithoutBouncesItAgreesWithTheDirectPassForAreaLightsAndTheSky) {
    const Camera camera = Camera::lookAt({0.8, 1.5, 2.0}, {0.0, 0.3, 0.0}, {0, 1, 0}, 0.9);
    std::vector<Light> areas(2);
    areas[0].type = LightType::Sphere;
    areas[0].position = glm::vec3(0.7f, 1.0f, 0.5f);
    areas[0].radius = 0.15f;
    areas[0].range = 10.0f;
    areas[1].type = LightType::Rectangle;
    areas[1].position = glm::vec3(-0.6f, 1.2f, 0.2f);
    areas[1].direction = glm::vec3(0.0f, -1.0f, 0.0f);
    areas[1].up = glm::vec3(0.0f, 0.0f, 1.0f);
    areas[1].width = 0.4f;
    areas[1].height = 0.3f;
    areas[1].range = 10.0f;
    auto compare = [&](bool box, const std::vector<Light>& lights, const char* what,
                       bool sheet = false) {
        Scene scene = emptyScene();
        addFloor(scene, 2.0f);
        if (box) addBox(scene, {-0.3f, 0.0f, -0.3f}, {0.3f, 0.6f, 0.3f});
        if (sheet) {
            // Above the camera: a black sheet of coverage 0.25 (glTF BLEND).
            Material m = scene.materials[0];
            m.baseColor = glm::vec3(0.0f);
            m.alphaMode = AlphaMode::Blend;
            m.alpha = 0.25f;
            scene.materials.push_back(m);
            addQuad(scene, {-20, 2, -20}, {20, 2, -20}, {20, 2, 20}, {-20, 2, 20},
                    int(scene.materials.size()) - 1);
        }
        const ImageBuf gbuf = gbufferOf(scene, camera, 48, 36);
        const RayCaster caster(scene);
        LightingParams p;
        p.shadowSamples = 256;
        p.environmentSamples = 256;
        p.denoise = false;
        const ImageBuf direct = shade(gbuf, lights, &caster, p);
        const ImageBuf path = pathTraced(gbuf, lights, caster, 256, 0);
        double a = 0.0, b = 0.0, squares = 0.0;
        int n = 0;
        for (int y = 0; y < 36; ++y)
            for (int x = 0; x < 48; ++x) {
                if (!covered(gbuf, x, y)) continue;
                const double la = luminance(glm::make_vec3(px(direct, x, y)));
                const double lb = luminance(glm::make_vec3(px(path, x, y)));
                a += la;
                b += lb;
                squares += (la - lb) * (la - lb);
                ++n;
            }
        const double rms = std::sqrt(squares / n) / (a / n);
        std::printf("%s: direct pass %.5f, path traced %.5f (%+.2f %%), RMS of the difference "
                    "%.2f %%\n",
                    what, a / n, b / n, 100.0 * (b / a - 1.0), 100.0 * rms);
        EXPECT_NEAR(b / a, 1.0, 0.01) << what;
        EXPECT_LT(rms, sheet ? 0.05 : 0.03) << what; // the sheet's coin flips add noise
    };
    compare(true, areas, "sphere and rectangle lights, box");
    Light sky = uniformSky();
    sky.intensity = 0.2f;
    compare(false, {sky}, "sky, floor");
    // Paths pass a Blend surface by its coverage, as the shadow rays do.
    compare(false, {sky}, "sky through a sheet of coverage 0.25, floor", true);
}

// The room in the metal: a white metal box (roughness 0.3) in a room with a red and a green
// wall under a point light. Over the box's pixels the deferred pass with its specular indirect
// light (64 rays a pixel, undenoised) gathers what a path of one bounce gathers: the mean of
// each channel within 3 % of the path tracer's (256 paths; measured 0.4 %; the issue asks for
// 10 %), which the direct light alone misses ninefold.
TEST(PathTracer, TheSpecularIndirectLightIsTheRoomInTheMetal) {
    const Scene scene = metalBoxInARoom(glm::vec3(1.0f), 0.3f, false);
    const ImageBuf gbuf = gbufferOf(scene, kRoomCamera, 48, 48);
    const RayCaster caster(scene);
    const Light light = roomLight();
    auto deferred = [&](int samples) {
        LightingParams p;
        p.specularSamples = samples;
        p.denoise = false;
        LightingInputs inputs{{light}, &caster};
        inputs.scene = &caster;
        ImageBuf out;
        EXPECT_TRUE(shadeGBuffer(out, gbuf, inputs, p)) << out.geterror();
        return out;
    };
    const ImageBuf with = deferred(64), without = deferred(0);
    const ImageBuf path = pathTraced(gbuf, {light}, caster, 256, 1);
    glm::dvec3 a, b, c, unused;
    const int n = boxMeans(gbuf, 48, 48, with, path, a, b);
    boxMeans(gbuf, 48, 48, without, path, c, unused);
    std::printf("the metal box over %d pixels: with specular indirect %.4f %.4f %.4f, path "
                "traced %.4f %.4f %.4f, direct only %.4f %.4f %.4f\n",
                n, a.r, a.g, a.b, b.r, b.g, b.b, c.r, c.g, c.b);
    ASSERT_GT(n, 300);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(a[k] / b[k], 1.0, 0.03) << "channel " << k;
        EXPECT_LT(c[k] / b[k], 0.8) << "channel " << k;
    }
}

// A rough metal (roughness 0.7) in the coloured box, with probes: its lobe is too wide for rays
// to pay (SpecularIndirect::traced) and reflects the probes' irradiance by its albedo, as the
// bake's hits do. Over the metal box's pixels, the frame's colour and mean against 256 paths of
// 8 bounces, within 10 % per channel (issue 23's goal for a metal in a coloured box).
TEST(PathTracer, ARoughMetalInTheRoomTakesTheProbesLight) {
    const Scene scene = metalBoxInARoom(glm::vec3(0.95f, 0.9f, 0.85f), 0.7f, true);
    const ImageBuf gbuf = gbufferOf(scene, kRoomCamera, 48, 48);
    const RayCaster caster(scene);
    const Light light = roomLight();
    const ProbeVolume probes = bakedProbes(scene, caster, {light}, 0.25);
    LightingParams p;
    LightingInputs inputs{{light}, &caster};
    inputs.scene = &caster;
    inputs.probes = &probes;
    ImageBuf with;
    LightingStats stats;
    ASSERT_TRUE(shadeGBuffer(with, gbuf, inputs, p, {}, 0, &stats)) << with.geterror();
    const ImageBuf path = pathTraced(gbuf, {light}, caster, 256, 8);
    glm::dvec3 a, b;
    const int n = boxMeans(gbuf, 48, 48, with, path, a, b);
    std::printf("the rough metal box over %d pixels: probes %.4f %.4f %.4f, path traced %.4f "
                "%.4f %.4f; %lld specular rays\n",
                n, a.r, a.g, a.b, b.r, b.g, b.b, stats.specularRays);
    ASSERT_GT(n, 300);
    EXPECT_EQ(stats.specularRays, 0);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(a[k] / b[k], 1.0, 0.1) << "channel " << k;
}

// A metal box (roughness 0.3, its reflection traced) on a white floor under a uniform sky, with
// probes: what its rays hit is lit as the frame is, the sky's diffuse light through the probes
// only (not also by the environment's irradiance) and the hit's rough specular lobe by the
// probes too. Over the box's pixels within 5 % of 256 paths of 8 bounces per channel; with the
// sky's diffuse light counted twice at the hits the box was +70 % (the floor's reflection).
TEST(PathTracer, TheSkyIsCountedOnceWhereReflectionsHitWithProbes) {
    Scene scene = emptyScene();
    Material metal = scene.materials[0];
    metal.baseColor = glm::vec3(0.9f);
    metal.metallic = 1.0f;
    metal.roughness = 0.3f;
    scene.materials.push_back(metal);
    addFloor(scene, 3.0f);
    const size_t before = scene.meshes.size();
    addBox(scene, {-0.3f, 0.0f, -0.3f}, {0.3f, 0.6f, 0.3f});
    for (size_t m = before; m < scene.meshes.size(); ++m)
        scene.meshes[m].material = 1;
    const Camera camera = Camera::lookAt({0.9, 0.9, 1.4}, {0.0, 0.3, 0.0}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(scene, camera, 48, 36);
    const RayCaster caster(scene);
    Light sky = uniformSky();
    sky.intensity = 0.5f;
    const ProbeVolume probes = bakedProbes(scene, caster, {sky}, 0.3);
    LightingParams p;
    p.specularSamples = 64;
    p.environmentSamples = 64;
    p.denoise = false;
    LightingInputs inputs{{sky}, &caster};
    inputs.scene = &caster;
    inputs.probes = &probes;
    ImageBuf with;
    ASSERT_TRUE(shadeGBuffer(with, gbuf, inputs, p)) << with.geterror();
    const ImageBuf path = pathTraced(gbuf, {sky}, caster, 256, 8);
    glm::dvec3 a, b;
    const int n = boxMeans(gbuf, 48, 36, with, path, a, b, 0.601f, 0.001f);
    std::printf("the metal box under the sky over %d pixels: deferred with probes %.4f %.4f %.4f, "
                "path traced %.4f %.4f %.4f\n",
                n, a.r, a.g, a.b, b.r, b.g, b.b);
    ASSERT_GT(n, 100);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(a[k] / b[k], 1.0, 0.05) << "channel " << k;
}

// With probes, an environment lights a rough surface through them alone (its diffuse light and
// the rough lobe's): no shadow ray of the environment is traced there, and the frame is the
// frame without the environment's shadow rays, bit for bit.
TEST(PathTracer, WithProbesRoughSurfacesTraceNoEnvironmentRays) {
    Scene scene = emptyScene();
    scene.materials[0].roughness = 0.8f;
    addFloor(scene, 3.0f);
    addBox(scene, {-0.3f, 0.0f, -0.3f}, {0.3f, 0.6f, 0.3f});
    const Camera camera = Camera::lookAt({0.9, 0.9, 1.4}, {0.0, 0.3, 0.0}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(scene, camera, 48, 36);
    const RayCaster caster(scene);
    Light sky = uniformSky();
    sky.intensity = 0.5f;
    const ProbeVolume probes = bakedProbes(scene, caster, {sky}, 0.5);
    auto frame = [&](int environmentSamples, LightingStats& stats) {
        LightingParams p;
        p.environmentSamples = environmentSamples;
        LightingInputs inputs{{sky}, &caster};
        inputs.scene = &caster;
        inputs.probes = &probes;
        ImageBuf out;
        EXPECT_TRUE(shadeGBuffer(out, gbuf, inputs, p, {}, 0, &stats)) << out.geterror();
        return out;
    };
    LightingStats traced, untraced;
    const ImageBuf a = frame(16, traced), b = frame(0, untraced);
    EXPECT_EQ(traced.shadowRays, 0);
    const auto cmp = OIIO::ImageBufAlgo::compare(a, b, 0.0f, 0.0f);
    EXPECT_EQ(cmp.nfail, 0u) << "max error " << cmp.maxerror;
}

// Probes against the reference on the Cornell box (its own lights and glowing panel), per
// surface: the indirect light (the frame with probes, or path traced, less the direct-only
// frame) as mean luminance over each object's pixels. Every wall and block within 5 % of
// 256 paths of 8 bounces (issue 23's goal), at the default spacing (8 × 8 × 8 probes, as at
// the box's real scale): the worst is the tall block, −3.3 %, and the back wall +3.0 % (+4.5 %
// with the grid's outer layers half a spacing from the walls instead of a quarter; 8 × 8 maps:
// the blocks +3.8 % and +3.4 %, and at real scale +10.9 %: docs/gi.md). Before the rough
// specular lobe took the probes' light and the lookup extrapolated to the bounds, the red wall
// was −15 % and the green −10 %.
TEST(PathTracer, ProbesAgreeWithItPerSurfaceOnTheCornellBox) {
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(std::string(DHDR_TESTDATA) + "/cornell_box.gltf", scene, error)) << error;
    ASSERT_FALSE(scene.cameras.empty());
    std::vector<Light> lights = scene.lights;
    const std::vector<Light> glowing = emissiveLights(scene);
    lights.insert(lights.end(), glowing.begin(), glowing.end());
    const RayCaster caster(scene);
    ProbeBakeParams bake;
    ProbeVolume probes;
    ASSERT_TRUE(bakeProbes(scene, caster, lights, true, bake, probes, error)) << error;
    EXPECT_EQ(probes.counts, glm::ivec3(8));
    constexpr int W = 96, H = 96;
    const ImageBuf gbuf = gbufferOf(scene, scene.cameras[0].camera, W, H);
    const ImageBuf direct = deferredFrame(gbuf, lights, caster, nullptr),
                   withProbes = deferredFrame(gbuf, lights, caster, &probes);
    const ImageBuf path = pathTraced(gbuf, lights, caster, 256, 8);
    const int idc = gbuf.spec().channelindex("id.object");
    ASSERT_GE(idc, 0);
    const auto sums =
        indirectPerSurface(gbuf, direct, withProbes, path, nullptr,
                           [&](int x, int y) { return int(std::lround(px(gbuf, x, y)[idc])); });
    int surfaces = 0;
    for (const auto& [id, s] : sums) {
        // id.object counts the scene's objects from 1.
        const std::string name = id >= 1 && id <= int(scene.objectNames.size())
                                     ? scene.objectNames[size_t(id - 1)]
                                     : "?";
        const double a = luminanceOf(s.probesMean()), b = luminanceOf(s.pathMean());
        std::printf("%-12s %5d px: probes %.5f, path traced %.5f (%+.1f %%)\n", name.c_str(),
                    s.pixels, a, b, 100.0 * (a / b - 1.0));
        if (name == "light" || s.pixels < 200) continue; // the lamp panel: −10 %, docs/gi.md
        EXPECT_NEAR(a / b, 1.0, 0.05) << name;
        ++surfaces;
    }
    EXPECT_EQ(surfaces, 7);
}

namespace {

// Two closed rooms in [0, 2] × [0, 1] × [0, 1] split by a closed wall 3 cm thick at x = 0.86
// (as in Probes.NoLightLeaksThroughAClosedWall), which holds the column x = 0.879 of a
// 0.125 m grid's points (0.1212 apart, the outer ones a quarter of that inside); each face its
// own object, a red outer wall and a green block in room A (x < 0.86), a blue outer wall and a
// grey block in room B.
const char* const kTwoRoomsObjects[] = {"back wall",  "front wall", "left wall",
                                        "right wall", "floor",      "ceiling",
                                        "divider",    "block A",    "block B"};
constexpr float kDividerLo = 0.86f, kDividerHi = 0.89f;

Scene twoRooms() {
    Scene scene = emptyScene();
    Material red = scene.materials[0], green = red, blue = red, grey = red;
    red.baseColor = glm::vec3(0.7f, 0.1f, 0.1f);
    green.baseColor = glm::vec3(0.1f, 0.6f, 0.1f);
    blue.baseColor = glm::vec3(0.15f, 0.2f, 0.7f);
    grey.baseColor = glm::vec3(0.5f);
    scene.materials.insert(scene.materials.end(), {red, green, blue, grey});
    scene.objectNames.assign(std::begin(kTwoRoomsObjects), std::end(kTwoRoomsObjects));
    // The shell: addBox's six faces (−z, +z, −x, +x, −y, +y) turned inwards.
    addBox(scene, {0, 0, 0}, {2, 1, 1});
    for (size_t m = 0; m < 6; ++m) {
        Mesh& mesh = scene.meshes[m];
        for (glm::uvec3& t : mesh.triangles)
            std::swap(t.y, t.z);
        for (glm::vec3& n : mesh.normals)
            n = -n;
        mesh.object = int(m);
    }
    scene.meshes[2].material = 1; // left wall (x = 0), room A: red
    scene.meshes[3].material = 3; // right wall (x = 2), room B: blue
    auto box = [&](glm::vec3 lo, glm::vec3 hi, int material, int object) {
        const size_t before = scene.meshes.size();
        addBox(scene, lo, hi);
        for (size_t m = before; m < scene.meshes.size(); ++m)
            scene.meshes[m].material = material, scene.meshes[m].object = object;
    };
    box({kDividerLo, 0, 0}, {kDividerHi, 1, 1}, 0, 6);
    box({0.45f, 0, 0.3f}, {0.7f, 0.35f, 0.55f}, 2, 7);
    box({1.2f, 0, 0.25f}, {1.5f, 0.5f, 0.55f}, 4, 8);
    return scene;
}

} // namespace

// Probes against the reference in the two rooms, per surface and per room: room A lit by a
// yellow point light (red and green only), room B by a blue one, so that each room's light is
// in channels the other's has none of, and a leak through the wall shows in them. Each
// surface's indirect light (as on the Cornell box) in its room's channels within 5 % of the
// path tracer, whose standard error (from its paths' two halves) is held under 1 %; the path
// tracer's other channels exactly 0 (no path crosses the wall), the probes' under 1 % of
// what the other room holds in them. For probes at 0.125, at 0.25 and at the default (512
// probes): measured −1.3 to +2.8 %, +3.9 % and +3.1 % at most; with the grid's outer layers
// half a spacing from the walls instead of a quarter, up to +4.1, +11 and +4.8 % (docs/gi.md).
TEST(PathTracer, ProbesAgreeWithItPerSurfaceInTheTwoRooms) {
    const Scene scene = twoRooms();
    const RayCaster caster(scene);
    Light a, b;
    a.position = glm::vec3(0.35f, 0.75f, 0.45f);
    a.color = glm::vec3(1.0f, 1.0f, 0.0f);
    b.position = glm::vec3(1.55f, 0.75f, 0.6f);
    b.color = glm::vec3(0.0f, 0.0f, 1.0f);
    b.intensity = 1.5f;
    const std::vector<Light> lights = {a, b};
    // Three grids against the same paths: 0.125 (a column of grid points in the wall), 0.25
    // and the default (512 probes).
    const double spacings[] = {0.125, 0.25, 0.0};
    std::vector<ProbeVolume> volumes;
    for (const double spacing : spacings)
        volumes.push_back(bakedProbes(scene, caster, lights, spacing));
    const ProbeVolume& probes = volumes[0];
    int inWall = 0; // grid points inside the divider, which the bake must move or switch off
    for (int p = 0; p < probes.probeCount(); ++p) {
        const double x = probes.gridPoint({p % probes.counts.x, 0, 0}).x;
        if (x > kDividerLo && x < kDividerHi) {
            ++inWall;
            EXPECT_NE(probes.states[size_t(p)], ProbeState::Active);
        }
    }
    EXPECT_GT(inWall, 0);
    // 192 paths over 64 × 64 pixels: a standard error of 0.2-0.8 % per surface (printed; at
    // 128 paths the green block's red channel, its albedo 0.1, was ± 0.95 %).
    // Closed rooms keep most of the light bounce after bounce (room A's red channel: about
    // 0.8 a bounce), so 8 bounces would leave out 0.8⁸ ≈ 17 % of it; Russian roulette ends
    // the paths.
    constexpr int W = 64, H = 64, kPaths = 192, kBounces = 64;
    // One view into each room from just inside its front wall.
    const double middle[2] = {0.5 * kDividerLo, 0.5 * (kDividerHi + 2.0)};
    std::map<int, IndirectSums> sums[3]; // per grid; surface = object × 2 + room
    for (int room = 0; room < 2; ++room) {
        const Camera camera =
            Camera::lookAt({middle[room], 0.5, 0.97}, {middle[room], 0.45, 0.0}, {0, 1, 0}, 1.3);
        const ImageBuf gbuf = gbufferOf(scene, camera, W, H);
        const ImageBuf direct = deferredFrame(gbuf, lights, caster, nullptr);
        const ImageBuf path = pathTraced(gbuf, lights, caster, kPaths, kBounces),
                       half = pathTraced(gbuf, lights, caster, kPaths / 2, kBounces);
        const int idc = gbuf.spec().channelindex("id.object");
        ASSERT_GE(idc, 0);
        for (size_t grid = 0; grid < volumes.size(); ++grid) {
            const ImageBuf withProbes = deferredFrame(gbuf, lights, caster, &volumes[grid]);
            const auto own =
                indirectPerSurface(gbuf, direct, withProbes, path, &half, [&](int x, int y) {
                    // The divider's faces belong to the rooms they face.
                    const int object = int(std::lround(px(gbuf, x, y)[idc])) - 1;
                    return object * 2 +
                           (positionOf(gbuf, x, y).x > 0.5f * (kDividerLo + kDividerHi));
                });
            sums[grid].insert(own.begin(), own.end());
        }
    }
    // Each room's mean indirect light over its surfaces' pixels, per channel.
    glm::dvec3 roomMean[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
    int roomPixels[2] = {0, 0};
    for (const auto& [surface, s] : sums[0])
        roomMean[surface % 2] += s.path, roomPixels[surface % 2] += s.pixels;
    for (int room = 0; room < 2; ++room)
        roomMean[room] /= double(std::max(roomPixels[room], 1));
    const glm::bvec3 litIn[2] = {{true, true, false}, {false, false, true}};
    int compared = 0;
    for (size_t grid = 0; grid < volumes.size(); ++grid) {
        std::printf("spacing %.4g (%d probes):\n", volumes[grid].spacing.x,
                    volumes[grid].probeCount());
        for (const auto& [surface, s] : sums[grid]) {
            const int room = surface % 2, object = surface / 2;
            const std::string name =
                std::string(kTwoRoomsObjects[object]) + (room ? " (B)" : " (A)");
            const glm::dvec3 p = s.probesMean(), t = s.pathMean(), se = s.standardError();
            std::printf("%-15s %4d px: probes %.4f %.4f %.4f, path traced %.4f %.4f %.4f:",
                        name.c_str(), s.pixels, p.r, p.g, p.b, t.r, t.g, t.b);
            for (int k = 0; k < 3; ++k)
                if (litIn[room][k])
                    std::printf(" %+.1f %% (± %.2f %%)", 100.0 * (p[k] / t[k] - 1.0),
                                100.0 * se[k] / t[k]);
            std::printf("\n");
            for (int k = 0; k < 3; ++k) {
                if (litIn[room][k]) {
                    if (s.pixels < 100) continue; // a sliver
                    EXPECT_LT(se[k] / t[k], 0.01) << name << " channel " << k;
                    EXPECT_NEAR(p[k] / t[k], 1.0, 0.05)
                        << name << " channel " << k << " spacing " << spacings[grid];
                    ++compared;
                } else {
                    // The other room's light: none in the path tracer, a trace in the probes.
                    EXPECT_EQ(t[k], 0.0) << name << " channel " << k;
                    EXPECT_LT(std::abs(p[k]), 0.01 * roomMean[1 - room][k])
                        << name << " channel " << k << " spacing " << spacings[grid];
                }
            }
        }
    }
    // Floor, ceiling, back wall, outer wall, divider and block in each room, in its channels,
    // for each grid.
    EXPECT_EQ(compared, 3 * (6 * 2 + 6));
}
