// Visibility in the lighting pass against independent answers: analytic shadow regions and
// penumbrae, closed forms of ambient occlusion, Monte Carlo against exact irradiance, and the
// culled pass against brute force with shadow rays.
#include "denoise/denoise_lanes.h"
#include "gi/bounce_light.h"
#include "scene_builder.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <cstring>
#include <dhdr/deferred/core/cpu_features.h>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/denoise/denoise.h>
#include <dhdr/deferred/direct/ambient_occlusion.h>
#include <dhdr/deferred/direct/shadows.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/shading_point.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/lights/area.h>
#include <dhdr/deferred/lights/emissive_lights.h>
#include <dhdr/deferred/lights/light.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/scene.h>
#include <gtest/gtest.h>
#include <random>

using namespace dhdr;
using namespace dhdr::test;
using OIIO::ImageBuf;

namespace {

[[maybe_unused]] auto* const kKernel = ::testing::AddGlobalTestEnvironment(new EmbreeKernel);

// Shades `gbuf` in strips of `rows` rows, each cut with the denoiser's reach of rows above and
// below (as dhdr-light reads them), with `carry` handed from strip to strip when given: the
// strips' pixels, and their rays in `stats`.
ImageBuf shadeInStrips(const ImageBuf& gbuf, LightingInputs inputs, LightingParams params, int rows,
                       EstimateCarry* carry, LightingStats& stats) {
    const OIIO::ROI frame = gbuf.roi();
    params.frame = frame;
    inputs.carry = carry;
    ImageBuf out(OIIO::ImageSpec(frame.width(), frame.height(), 4, OIIO::TypeDesc::FLOAT));
    for (int y = frame.ybegin; y < frame.yend; y += rows) {
        const OIIO::ROI own(frame.xbegin, frame.xend, y, std::min(frame.yend, y + rows));
        const OIIO::ROI band(frame.xbegin, frame.xend, std::max(frame.ybegin, y - kDenoiseReach),
                             std::min(frame.yend, own.yend + kDenoiseReach), 0, 1, 0,
                             gbuf.nchannels());
        ImageBuf strip = OIIO::ImageBufAlgo::cut(gbuf, band);
        strip.set_origin(band.xbegin, band.ybegin);
        ImageBuf lit;
        LightingStats part;
        EXPECT_TRUE(shadeGBuffer(lit, strip, inputs, params, own, 2, &part)) << lit.geterror();
        stats += part;
        // paste's position is an offset from the region's own.
        EXPECT_TRUE(OIIO::ImageBufAlgo::paste(
            out, 0, 0, 0, 0, lit,
            OIIO::ROI(own.xbegin, own.xend, own.ybegin, own.yend, 0, 1, 0, 4)))
            << out.geterror();
    }
    return out;
}

glm::vec3 positionAt(const ImageBuf& gbuf, int x, int y) {
    const float* g = px(gbuf, x, y);
    const int c = gbuf.spec().channelindex("P.X");
    return {g[c], g[c + 1], g[c + 2]};
}

// Does the segment from p to q pass through the box [lo, hi] (slab test in double)?
bool segmentHitsBox(glm::dvec3 p, glm::dvec3 q, glm::dvec3 lo, glm::dvec3 hi) {
    double t0 = 0.0, t1 = 1.0;
    const glm::dvec3 d = q - p;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-300) {
            if (p[a] < lo[a] || p[a] > hi[a]) return false;
            continue;
        }
        double ta = (lo[a] - p[a]) / d[a], tb = (hi[a] - p[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) return false;
    }
    return true;
}

struct BoxShadowCounts {
    int shadowed = 0, lit = 0, footShadowed = 0;
};

// A box over (or on) a floor under one point light: every floor pixel whose segment to the
// light passes through the box (shrunk by a margin) is exactly 0, every one whose segment
// misses the box (grown by the margin) is exactly the unshadowed value.
BoxShadowCounts checkBoxShadow(glm::vec3 lo, glm::vec3 hi) {
    Scene scene = emptyScene();
    addFloor(scene, 3.0f);
    addBox(scene, lo, hi);
    Light light;
    light.type = LightType::Point;
    light.position = {0.9f, 1.6f, 0.4f};
    light.intensity = 2.0f;
    const Camera camera = Camera::lookAt({-0.5, 3.0, 2.5}, {-0.4, 0.0, -0.2}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(scene, camera, 240, 180);
    const RayCaster caster(scene);
    const ImageBuf lit = shade(gbuf, {light}, &caster);
    const ImageBuf reference = shade(gbuf, {light}, nullptr);
    const double margin = 1e-4;
    const glm::dvec3 m(margin);
    BoxShadowCounts counts;
    for (int y = 0; y < 180; ++y)
        for (int x = 0; x < 240; ++x) {
            if (!(px(gbuf, x, y)[gbuf.spec().channelindex("A")] > 0.0f)) continue;
            const glm::dvec3 P(positionAt(gbuf, x, y));
            if (std::abs(P.y) > 1e-6) continue; // the floor only
            const glm::dvec3 L(light.position);
            const float* v = px(lit, x, y);
            const float* r = px(reference, x, y);
            if (segmentHitsBox(P, L, glm::dvec3(lo) + m, glm::dvec3(hi) - m)) {
                ++counts.shadowed;
                if (v[0] != 0.0f || v[1] != 0.0f || v[2] != 0.0f) {
                    ADD_FAILURE() << "lit inside the shadow at " << x << "," << y;
                    return counts;
                }
                const double toFoot = std::min({std::abs(P.x - lo.x), std::abs(P.x - hi.x),
                                                std::abs(P.z - lo.z), std::abs(P.z - hi.z)});
                if (lo.y == 0.0f && toFoot < 0.01) ++counts.footShadowed;
            } else if (!segmentHitsBox(P, L, glm::dvec3(lo) - m, glm::dvec3(hi) + m)) {
                ++counts.lit;
                EXPECT_GT(r[0], 0.0f);
                if (v[0] != r[0] || v[1] != r[1] || v[2] != r[2]) {
                    ADD_FAILURE() << "acne outside the shadow at " << x << "," << y;
                    return counts;
                }
            }
        }
    return counts;
}

} // namespace

TEST(Shadows, FloatingBoxCastsItsAnalyticShadowWithoutAcne) {
    const BoxShadowCounts n = checkBoxShadow({-0.3f, 0.4f, -0.3f}, {0.2f, 0.8f, 0.1f});
    EXPECT_GT(n.shadowed, 1000);
    EXPECT_GT(n.lit, 10000);
}

TEST(Shadows, BoxOnTheFloorLeavesNoLitGapAtItsFoot) {
    const BoxShadowCounts n = checkBoxShadow({-0.3f, 0.0f, -0.3f}, {0.2f, 0.5f, 0.1f});
    EXPECT_GT(n.shadowed, 300);
    // Pixels within 1 cm of the foot on the shadowed side were checked to be dark.
    EXPECT_GT(n.footShadowed, 20);
}

// A sphere light over the straight edge of a horizontal sheet: the penumbra on the floor lies
// between the two planes through the edge tangent to the sphere.
TEST(Shadows, SphereLightPenumbraMatchesTheGeometricConstruction) {
    Scene scene = emptyScene();
    addFloor(scene, 4.0f);
    const float h = 0.5f; // the sheet covers x < 0 at height h
    addQuad(scene, {-4, h, -4}, {-4, h, 4}, {0, h, 4}, {0, h, -4});
    Light light;
    light.type = LightType::Sphere;
    light.position = {0.3f, 1.0f, 0.0f};
    light.radius = 0.1f;
    light.intensity = 1.0f;
    // Low, under the sheet, looking along −z at the floor around the shadow's edge.
    const Camera camera = Camera::lookAt({-0.3, 0.3, 1.5}, {-0.3, 0.0, 0.0}, {0, 1, 0}, 0.7);
    const int W = 320, H = 200;
    const ImageBuf gbuf = gbufferOf(scene, camera, W, H);
    const RayCaster caster(scene);
    LightingParams p;
    p.shadowSamples = 256;
    const ImageBuf lit = shade(gbuf, {light}, &caster, p);
    const ImageBuf reference = shade(gbuf, {light}, nullptr);

    // The lines through the edge (0, h) tangent to the light's circle, where they meet y = 0.
    const double ex = light.position.x, ey = light.position.y - h;
    const double L = std::hypot(ex, ey), phi = std::atan2(ey, ex), spread = std::asin(0.1 / L);
    double x1 = -h / std::tan(phi + spread), x2 = -h / std::tan(phi - spread);
    if (x1 > x2) std::swap(x1, x2);

    double lo = INFINITY, hi = -INFINITY, footprint = 0.0;
    int dark = 0, full = 0, penumbra = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x + 1 < W; ++x) {
            const glm::vec3 P = positionAt(gbuf, x, y);
            if (!(px(gbuf, x, y)[gbuf.spec().channelindex("A")] > 0.0f) || std::abs(P.y) > 1e-6 ||
                std::abs(P.z) > 0.3f)
                continue;
            footprint = std::max(footprint, double(std::abs(positionAt(gbuf, x + 1, y).x - P.x)));
            const float v = px(lit, x, y)[0], r = px(reference, x, y)[0];
            ASSERT_GT(r, 0.0f) << P.x << " " << P.y << " " << P.z << " at " << x << "," << y;
            if (P.x < x1 - 1e-3) {
                ASSERT_EQ(v, 0.0f) << "light inside the umbra at x = " << P.x;
                ++dark;
            } else if (P.x > x2 + 1e-3) {
                ASSERT_EQ(v, r) << "shadow outside the penumbra at x = " << P.x;
                ++full;
            }
            if (v > 0.0f && v < r) {
                lo = std::min(lo, double(P.x));
                hi = std::max(hi, double(P.x));
                ++penumbra;
            }
        }
    EXPECT_GT(dark, 500);
    EXPECT_GT(full, 500);
    EXPECT_GT(penumbra, 500);
    std::printf("penumbra measured [%.4f, %.4f], constructed [%.4f, %.4f], pixel %.4f\n", lo, hi,
                x1, x2, footprint);
    // Within two pixels of the construction at both ends.
    EXPECT_NEAR(lo, x1, 2.0 * footprint) << "penumbra [" << lo << ", " << hi << "], expected ["
                                         << x1 << ", " << x2 << "], pixel " << footprint;
    EXPECT_NEAR(hi, x2, 2.0 * footprint);
}

namespace {

// Ray-traced AO of the floor pixels of `scene` seen from straight above.
ImageBuf aoFromAbove(const Scene& scene, float distance, int samples, ImageBuf& gbuf) {
    Camera camera = Camera::lookAt({-0.5, 5.0, 0.0}, {-0.5, 0.0, 0.0}, {0, 0, -1}, 0.5);
    camera.orthographic = true;
    camera.ymag = 0.6;
    gbuf = gbufferOf(scene, camera, 200, 200);
    const RayCaster caster(scene);
    LightingParams p;
    p.aoSamples = samples;
    p.aoDistance = distance;
    p.writeAO = true;
    return shade(gbuf, {}, &caster, p);
}

// Share of cosine-weighted directions from a floor point that reach the wall x = a within
// distance D: those whose x component exceeds c = a / D. Integrated numerically over the
// hemisphere in double ...
double wallOcclusionIntegrated(double c) {
    const int n = 1000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double theta = (i + 0.5) / n * M_PI / 2;
        for (int j = 0; j < n; ++j) {
            const double phi = (j + 0.5) / n * 2 * M_PI;
            if (std::sin(theta) * std::cos(phi) > c) sum += std::cos(theta) * std::sin(theta);
        }
    }
    return sum * (M_PI / 2 / n) * (2 * M_PI / n) / M_PI;
}

// ... and in closed form: a cosine-weighted direction projects to a uniform point of the unit
// disk, so the share is the disk's segment beyond x = c over π.
double wallOcclusion(double a, double D) {
    const double c = std::min(a / D, 1.0);
    return (std::acos(c) - c * std::sqrt(1.0 - c * c)) / M_PI;
}

} // namespace

TEST(AmbientOcclusion, OpenPlaneIsExactlyOne) {
    Scene scene = emptyScene();
    addFloor(scene, 3.0f);
    ImageBuf gbuf;
    const ImageBuf ao = aoFromAbove(scene, 1.0f, 16, gbuf);
    const int c = ao.spec().channelindex("AO");
    ASSERT_EQ(c, 4);
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 200; ++x)
            ASSERT_EQ(px(ao, x, y)[c], 1.0f);
}

TEST(AmbientOcclusion, WallOcclusionClosedFormMatchesIntegration) {
    for (const double c : {0.0, 0.25, 0.5, 0.8})
        EXPECT_NEAR(wallOcclusion(c, 1.0), wallOcclusionIntegrated(c), 2e-4) << c;
}

TEST(AmbientOcclusion, FloorBesideAnInfiniteWall) {
    // The wall x = 0 (facing −x, 1 km high and wide) beside the floor x < 0.
    Scene scene = emptyScene();
    addQuad(scene, {-1000, 0, -1000}, {-1000, 0, 1000}, {0, 0, 1000}, {0, 0, -1000});
    addQuad(scene, {0, 0, -1000}, {0, 0, 1000}, {0, 1000, 1000}, {0, 1000, -1000});
    for (const double D : {1e30, 1.0, 0.5}) {
        ImageBuf gbuf;
        const ImageBuf ao = aoFromAbove(scene, float(D), 16, gbuf);
        // Bins of distance to the wall; in each the mean AO against the mean closed form.
        constexpr int kBins = 5;
        double got[kBins] = {}, want[kBins] = {};
        int count[kBins] = {};
        for (int y = 0; y < 200; ++y)
            for (int x = 0; x < 200; ++x) {
                const glm::vec3 P = positionAt(gbuf, x, y);
                if (!(px(gbuf, x, y)[gbuf.spec().channelindex("A")] > 0.0f) ||
                    std::abs(P.y) > 1e-6 || P.x > -0.01f)
                    continue;
                const double a = -P.x;
                const int bin = std::min(kBins - 1, int(a / 1.1 * kBins));
                got[bin] += px(ao, x, y)[4];
                want[bin] += 1.0 - wallOcclusion(a, D);
                ++count[bin];
            }
        for (int b = 0; b < kBins; ++b) {
            ASSERT_GT(count[b], 500);
            // 16 rays per pixel, > 500 pixels per bin: the standard error is below 0.006.
            EXPECT_NEAR(got[b] / count[b], want[b] / count[b], 0.025)
                << "distance " << D << ", bin " << b;
        }
        if (D > 1e20) {
            EXPECT_NEAR(want[0] / count[0], 0.5, 1e-3); // the closed form, ½
        }
    }
}

TEST(AmbientOcclusion, OccludesOnlyTheAmbientLight) {
    Scene scene = emptyScene();
    addQuad(scene, {-1000, 0, -1000}, {-1000, 0, 1000}, {0, 0, 1000}, {0, 0, -1000});
    addQuad(scene, {0, 0, -1000}, {0, 0, 1000}, {0, 1000, 1000}, {0, 1000, -1000});
    Camera camera = Camera::lookAt({-0.5, 5.0, 0.0}, {-0.5, 0.0, 0.0}, {0, 0, -1}, 0.5);
    const ImageBuf gbuf = gbufferOf(scene, camera, 64, 64);
    const RayCaster caster(scene);
    Light ambient;
    ambient.type = LightType::Ambient;
    ambient.intensity = 1.0f;
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)); // away from the wall
    sun.intensity = 3.0f;
    LightingParams p;
    p.aoSamples = 16;
    p.writeAO = true;
    p.shadows = false;
    const ImageBuf both = shade(gbuf, {ambient, sun}, &caster, p);
    const ImageBuf ambientOnly = shade(gbuf, {ambient}, &caster, p);
    const ImageBuf sunOnly = shade(gbuf, {sun}, nullptr);
    const ImageBuf open = shade(gbuf, {ambient}, nullptr);
    int occluded = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const float ao = px(both, x, y)[4];
            occluded += ao < 1.0f;
            for (int c = 0; c < 3; ++c) {
                EXPECT_FLOAT_EQ(px(ambientOnly, x, y)[c], px(open, x, y)[c] * ao);
                EXPECT_FLOAT_EQ(px(both, x, y)[c], px(sunOnly, x, y)[c] + px(open, x, y)[c] * ao);
            }
        }
    EXPECT_GT(occluded, 1000);
}

// Σ L cos θ / pdf over many samples of each area light against its exact irradiance
// (sphereIrradiance, polygonIrradiance): the pdfs and radiances of sampleLi are consistent.
TEST(LightSampling, MonteCarloIrradianceMatchesTheExactValue) {
    Light sphere;
    sphere.type = LightType::Sphere;
    sphere.position = {0.3f, 1.2f, -0.2f};
    sphere.radius = 0.25f;
    sphere.intensity = 2.0f;
    Light rect;
    rect.type = LightType::Rectangle;
    rect.position = {-0.2f, 0.9f, 0.4f};
    rect.direction = glm::normalize(glm::vec3(0.2f, -1.0f, -0.1f));
    rect.up = glm::normalize(glm::cross(rect.direction, glm::vec3(1, 0, 0)));
    rect.width = 0.5f;
    rect.height = 0.3f;
    rect.intensity = 1.5f;
    Scene scene = emptyScene();
    scene.materials[0].emission = glm::vec3(3.0f, 2.0f, 1.0f);
    addQuad(scene, {-0.4f, 1.0f, -0.3f}, {0.3f, 1.1f, -0.3f}, {0.3f, 1.1f, 0.4f},
            {-0.4f, 1.0f, 0.4f});
    addQuad(scene, {0.5f, 0.4f, -0.3f}, {0.5f, 0.4f, 0.3f}, {0.5f, 1.0f, 0.3f},
            {0.5f, 1.0f, -0.3f}); // a second quad: the mesh light picks triangles by area
    scene.meshes[1].material = 0;
    Mesh merged = scene.meshes[0];
    for (const glm::vec3& v : scene.meshes[1].positions)
        merged.positions.push_back(v);
    merged.normals.insert(merged.normals.end(), scene.meshes[1].normals.begin(),
                          scene.meshes[1].normals.end());
    merged.triangles.push_back({4, 5, 6});
    merged.triangles.push_back({4, 6, 7});
    scene.meshes = {merged};
    const std::vector<Light> glowing = emissiveLights(scene);
    ASSERT_EQ(glowing.size(), 1u);
    const Light& mesh = glowing[0];

    const glm::vec3 P(0.0f, 0.0f, 0.0f), N = glm::normalize(glm::vec3(0.1f, 1.0f, 0.05f));
    auto exact = [&](const Light& l) -> double {
        if (l.type == LightType::Sphere)
            return sphereIrradiance(N, l.position - P, l.radius) * l.intensity /
                   (kPi * l.radius * l.radius);
        if (l.type == LightType::Rectangle) {
            glm::vec3 c[4];
            rectangleCorners(l, c);
            for (glm::vec3& v : c)
                v -= P;
            return polygonIrradiance(N, c, 4) * l.intensity / (l.width * l.height);
        }
        double e = 0.0;
        for (size_t t = 0; t < l.mesh->triangles(); ++t) {
            glm::vec3 v[3] = {l.mesh->vertices[3 * t] - P, l.mesh->vertices[3 * t + 1] - P,
                              l.mesh->vertices[3 * t + 2] - P};
            e += polygonIrradiance(N, v, 3);
        }
        return e * l.color.r;
    };
    for (const Light* l : std::initializer_list<const Light*>{&sphere, &rect, &mesh}) {
        const int n = 1 << 18;
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
            const LightLiSample s = sampleLi(*l, P, hammersley(std::uint32_t(i), n, 7));
            if (s.pdf > 0.0f) sum += double(s.L.r) * std::max(0.0f, glm::dot(N, s.wi)) / s.pdf;
        }
        EXPECT_NEAR(sum / n, exact(*l), 2e-3 * exact(*l)) << lightTypeName(l->type);
    }
}

TEST(EmissiveLights, AGlowingQuadLightsLikeTheRectangleLightItIs) {
    Scene scene = emptyScene();
    addFloor(scene, 2.0f);
    Material glow;
    glow.emission = glm::vec3(4.0f, 2.0f, 1.0f);
    glow.baseColor = glm::vec3(0.0f);
    scene.materials.push_back(glow);
    // A 0.4 × 0.2 panel at y = 1 facing down.
    addQuad(scene, {-0.2f, 1.0f, -0.1f}, {0.2f, 1.0f, -0.1f}, {0.2f, 1.0f, 0.1f},
            {-0.2f, 1.0f, 0.1f}, 1);
    const std::vector<Light> glowing = emissiveLights(scene);
    ASSERT_EQ(glowing.size(), 1u);
    EXPECT_EQ(glowing[0].type, LightType::Mesh);
    Light rect;
    rect.type = LightType::Rectangle;
    rect.position = {0.0f, 1.0f, 0.0f};
    rect.direction = {0.0f, -1.0f, 0.0f};
    rect.up = {0.0f, 0.0f, 1.0f};
    rect.width = 0.4f;
    rect.height = 0.2f;
    rect.color = glow.emission;
    rect.intensity = 0.08f; // radiance 1 × area: candela along the normal
    rect.range = glowing[0].range;
    const Camera camera = Camera::lookAt({0.0, 2.5, 2.0}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(scene, camera, 96, 64);
    const ImageBuf a = shade(gbuf, glowing, nullptr), b = shade(gbuf, {rect}, nullptr);
    int floor = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 96; ++x) {
            if (!(px(gbuf, x, y)[gbuf.spec().channelindex("A")] > 0.0f) ||
                std::abs(positionAt(gbuf, x, y).y) > 1e-6)
                continue;
            ++floor;
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(px(a, x, y)[c], px(b, x, y)[c], 1e-4 * px(b, x, y)[c] + 1e-7);
        }
    EXPECT_GT(floor, 2000);
}

namespace {
std::shared_ptr<const Ibl> sunOnlyEnvironment(const glm::vec3& sun);
} // namespace

// With 1,000 lights and shadow rays (and an environment with environment shadows), the culled
// pass equals brute force; the result does not
// depend on the thread count or on cutting the frame into strips.
TEST(Shadows, CulledEqualsBruteForceAndThreadsDoNotMatter) {
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(DHDR_TESTDATA "/cornell_box.gltf", scene, error)) << error;
    const ImageBuf gbuf = gbufferOf(scene, scene.cameras[0].camera, 160, 120);
    const RayCaster caster(scene);
    std::vector<Light> lights = emissiveLights(scene);
    std::uint64_t seed = 3;
    auto u = [&]() { return unitFloat(seed = mixBits(seed)); };
    for (int i = 0; i < 1000; ++i) {
        Light l;
        l.type = i % 3 == 0 ? LightType::Sphere : i % 3 == 1 ? LightType::Spot : LightType::Point;
        l.position = glm::vec3(0.05f + 0.45f * u(), 0.05f + 0.45f * u(), 0.05f + 0.45f * u());
        l.direction = glm::normalize(glm::vec3(u() - 0.5f, -1.0f, u() - 0.5f));
        l.radius = 0.01f + 0.02f * u();
        l.intensity = 0.002f + 0.01f * u();
        l.range = 0.05f + 0.2f * u();
        l.color = glm::vec3(u(), u(), u());
        lights.push_back(l);
    }
    Light ambient;
    ambient.type = LightType::Ambient;
    ambient.intensity = 0.05f;
    lights.push_back(ambient);
    Light sky;
    sky.type = LightType::Environment;
    sky.intensity = 0.02f;
    sky.rotation = 0.7f;
    sky.ibl = sunOnlyEnvironment(glm::normalize(glm::vec3(0.2f, 1.0f, -0.9f)));
    lights.push_back(sky);
    LightingParams p;
    p.aoSamples = 8;
    p.shadowSamples = 4;
    p.environmentSamples = 4;
    p.writeAO = true;
    LightingStats culledStats, bruteStats;
    const ImageBuf culled = shade(gbuf, lights, &caster, p, 2, &culledStats);
    p.bruteForce = true;
    const ImageBuf brute = shade(gbuf, lights, &caster, p, 2, &bruteStats);
    p.bruteForce = false;
    const ImageBuf oneThread = shade(gbuf, lights, &caster, p, 1);
    EXPECT_GT(culledStats.shadowRays, 100000);
    EXPECT_EQ(culledStats.shadowRays, bruteStats.shadowRays);
    double worst = 0.0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x)
            for (int c = 0; c < 5; ++c) {
                const float a = px(culled, x, y)[c], b = px(brute, x, y)[c];
                worst =
                    std::max(worst, std::abs(double(a) - b) / std::max(std::abs(double(b)), 1e-6));
                ASSERT_EQ(px(oneThread, x, y)[c], a)
                    << "thread count changed pixel " << x << "," << y;
            }
    EXPECT_LT(worst, 1e-5);
    // Strips of 37 rows, each read with the denoiser's reach of rows above and below (as
    // dhdr-light reads them), shade every pixel as the whole frame does; with an EstimateCarry
    // from strip to strip (as dhdr-light passes one), every row's rays are traced once: as many
    // as the whole frame's.
    for (const bool carrying : {false, true}) {
        EstimateCarry carry;
        LightingStats total;
        const ImageBuf lit =
            shadeInStrips(gbuf, {lights, &caster}, p, 37, carrying ? &carry : nullptr, total);
        for (int y = 0; y < 120; ++y)
            for (int x = 0; x < 160; ++x)
                for (int c = 0; c < 4; ++c)
                    ASSERT_EQ(px(lit, x, y)[c], px(culled, x, y)[c])
                        << x << "," << y << (carrying ? ", carried" : "");
        if (carrying) {
            EXPECT_EQ(total.shadowRays, culledStats.shadowRays);
            EXPECT_EQ(total.aoRays, culledStats.aoRays);
        } else {
            EXPECT_GT(total.shadowRays, culledStats.shadowRays); // the halos traced again
        }
    }
}

namespace {

// The corner of four 512 × 256 texels nearest `sun` that is the centre of one texel of the
// environment sampler's 256 × 128 table, so that the sun below fills that texel alone.
glm::ivec2 sunCorner(const glm::vec3& sun) {
    const glm::vec2 uv = equirectUV(sun);
    return {int(uv.x * 512) | 1, int(uv.y * 256) | 1};
}

// The direction of that corner: the sun's centre as the sampler sees it.
glm::vec3 sunCentre(const glm::vec3& sun) {
    const glm::ivec2 c = sunCorner(sun);
    return equirectDirection({float(c.x) / 512, float(c.y) / 256});
}

// An environment that is black but for a small bright sun around `sun` (2 × 2 texels of 0.7°).
std::shared_ptr<const Ibl> sunOnlyEnvironment(const glm::vec3& sun) {
    EnvironmentImage env;
    env.width = 512;
    env.height = 256;
    env.rgb.assign(size_t(512) * 256 * 3, 0.0f);
    const int sx = sunCorner(sun).x, sy = sunCorner(sun).y;
    for (int y = sy - 1; y <= sy; ++y)
        for (int x = sx - 1; x <= sx; ++x)
            for (int c = 0; c < 3; ++c)
                env.rgb[3 * (size_t(y) * 512 + size_t(x)) + size_t(c)] = 5000.0f;
    auto ibl = std::make_shared<Ibl>();
    std::string error;
    EXPECT_TRUE(bakeIbl(env, IblBakeParams{}, *ibl, error)) << error;
    return ibl;
}

} // namespace

// A box over a floor under an environment that is one small sun: with environment shadow rays,
// the floor is exactly unlit where the way to the sun passes through the box (shrunk by more
// than the sun's penumbra) and exactly the unshadowed value where it misses the grown box.
TEST(EnvironmentShadows, ASunInTheEnvironmentCastsTheBoxesShadow) {
    Scene scene = emptyScene();
    addFloor(scene, 3.0f);
    const glm::vec3 lo(-0.3f, 0.4f, -0.3f), hi(0.2f, 0.8f, 0.1f);
    addBox(scene, lo, hi);
    const glm::vec3 sun = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
    Light light;
    light.type = LightType::Environment;
    light.ibl = sunOnlyEnvironment(sun);
    // Its direction in the scene: the texels' centre, as the sampler sees them.
    const glm::vec3 centre = sunCentre(sun);
    const Camera camera = Camera::lookAt({-0.5, 3.0, 2.5}, {-0.4, 0.0, -0.2}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(scene, camera, 200, 150);
    const RayCaster caster(scene);
    LightingParams p;
    p.environmentSamples = 16;
    // Each pixel's own estimate: exact in both regions (the denoiser blurs across the edge).
    p.denoise = false;
    const ImageBuf lit = shade(gbuf, {light}, &caster, p);
    const ImageBuf reference = shade(gbuf, {light}, nullptr);
    // The sun spans one texel of the sampler (1.4°): at most 2.5 cm of penumbra at 1 m.
    const glm::dvec3 m(0.03);
    int dark = 0, bright = 0;
    for (int y = 0; y < 150; ++y)
        for (int x = 0; x < 200; ++x) {
            if (!(px(gbuf, x, y)[gbuf.spec().channelindex("A")] > 0.0f)) continue;
            const glm::dvec3 P(positionAt(gbuf, x, y));
            if (std::abs(P.y) > 1e-6) continue;
            const glm::dvec3 far = P + glm::dvec3(centre) * 10.0;
            const float* v = px(lit, x, y);
            const float* r = px(reference, x, y);
            if (segmentHitsBox(P, far, glm::dvec3(lo) + m, glm::dvec3(hi) - m)) {
                ++dark;
                // Black but for the grey occluder of the glossy lobe (shadows.h), lit by the
                // irradiance facing down from the box: zero but for the SH's ringing (1e-12).
                ASSERT_LT(v[0], 1e-9f) << x << "," << y;
            } else if (!segmentHitsBox(P, far, glm::dvec3(lo) - m, glm::dvec3(hi) + m)) {
                ++bright;
                ASSERT_GT(r[0], 0.0f);
                ASSERT_EQ(v[0], r[0]) << x << "," << y;
            }
        }
    EXPECT_GT(dark, 150);
    EXPECT_GT(bright, 5000);
}

namespace {

// A floor meeting a wall along the Z axis, seen from above at 48 × 48: the corner.
Scene floorAndWall() {
    Scene scene = emptyScene();
    addQuad(scene, {-1000, 0, -1000}, {-1000, 0, 1000}, {0, 0, 1000}, {0, 0, -1000});
    addQuad(scene, {0, 0, -1000}, {0, 0, 1000}, {0, 1000, 1000}, {0, 1000, -1000});
    return scene;
}
ImageBuf floorAndWallGBuffer(const Scene& scene) {
    const Camera camera = Camera::lookAt({-0.5, 5.0, 0.0}, {-0.5, 0.0, 0.0}, {0, 0, -1}, 0.5);
    return gbufferOf(scene, camera, 48, 48);
}

} // namespace

// AO scales the environment's diffuse light and, by Lagarde's specular occlusion, its
// specular light.
TEST(EnvironmentShadows, AmbientOcclusionOccludesTheEnvironment) {
    const Scene scene = floorAndWall();
    const ImageBuf gbuf = floorAndWallGBuffer(scene);
    const RayCaster caster(scene);
    const Light light = uniformSky();
    LightingParams p;
    p.aoSamples = 16;
    p.writeAO = true;
    p.environmentSamples = 0; // AO alone occludes here
    const ImageBuf occluded = shade(gbuf, {light}, &caster, p);
    const GBufferPixels g = [&] {
        GBufferPixels out;
        ImageBuf errors;
        EXPECT_TRUE(openGBuffer(gbuf, out, errors));
        return out;
    }();
    const GBufferView view(*g.pixels, g.layout, g.camera);
    int partial = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) {
            if (view.samples(x, y) == 0) continue;
            const ShadingPoint sp = view.at(x, y);
            const float ao = px(occluded, x, y)[4];
            const IblShading e = shadeEnvironment(light, sp.surface, sp.N, sp.V);
            const float so = specularOcclusion(glm::dot(sp.N, sp.V), ao, sp.surface.roughness);
            EXPECT_NEAR(px(occluded, x, y)[0], e.diffuse.r * ao + e.specular.r * so, 1e-5f);
            partial += ao < 1.0f;
        }
    EXPECT_GT(partial, 500);
}

// With shadow rays, an environment's visibility is traced: AO (which stands in for it) does
// not darken it a second time. The corner of the test above under the same sky, 16 rays:
// the picture with --ao rt (its AO written, and < 0.9 along the corner) is the picture
// without, bit for bit.
TEST(EnvironmentShadows, TracedVisibilityIsNotOccludedAgainByAO) {
    const Scene scene = floorAndWall();
    const ImageBuf gbuf = floorAndWallGBuffer(scene);
    const RayCaster caster(scene);
    LightingParams p;
    p.environmentSamples = 16;
    p.aoSamples = 0;
    const ImageBuf plain = shade(gbuf, {uniformSky()}, &caster, p);
    p.aoSamples = 16;
    p.writeAO = true;
    const ImageBuf withAO = shade(gbuf, {uniformSky()}, &caster, p);
    int occluded = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) {
            for (int c = 0; c < 4; ++c)
                ASSERT_EQ(px(withAO, x, y)[c], px(plain, x, y)[c]) << x << "," << y;
            occluded += px(withAO, x, y)[4] < 0.9f;
        }
    EXPECT_GT(occluded, 50);
}

namespace {

// A UV sphere of `segments` × `segments / 2` quads.
void addSphere(Scene& scene, glm::vec3 centre, float radius, int segments) {
    Mesh m;
    const int rings = segments / 2;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segments; ++j) {
            const float theta = kPi * float(i) / float(rings),
                        phi = 2 * kPi * float(j) / float(segments);
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                              std::sin(theta) * std::sin(phi));
            m.positions.push_back(centre + radius * n);
            m.normals.push_back(n);
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const unsigned a = unsigned(i * (segments + 1) + j), b = a + unsigned(segments) + 1;
            m.triangles.push_back({a, a + 1, b});
            m.triangles.push_back({a + 1, b + 1, b});
        }
    scene.meshes.push_back(m);
}

ImageBuf catcherFrame(const Scene& scene, const Light& light, ImageBuf& gbuf) {
    const Camera camera = Camera::lookAt({0.3, 2.5, 2.5}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.9);
    gbuf = gbufferOf(scene, camera, 160, 120);
    // dhdr-light's scene: the glTF's meshes, without the ground plane.
    Scene meshesOnly = scene;
    meshesOnly.hasGroundPlane = false;
    const RayCaster caster(meshesOnly);
    LightingParams p;
    p.environmentSamples = 16;
    p.denoise = false; // each pixel's own estimate, exact inside and outside the shadow
    return shade(gbuf, {light}, &caster, p);
}

} // namespace

namespace {

// A white mirror sphere of radius 1 at the origin, and a camera 4 units off that fills the
// frame with it: what the footprint tests below look at.
Scene mirrorSphere() {
    Scene scene = emptyScene();
    scene.materials[0].baseColor = glm::vec3(1.0f);
    scene.materials[0].roughness = 0.0f;
    scene.materials[0].metallic = 1.0f;
    addSphere(scene, {0.0f, 0.0f, 0.0f}, 1.0f, 128);
    return scene;
}

Camera mirrorSphereCamera() {
    return Camera::lookAt({0.0, 0.3, 4.0}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.6);
}

} // namespace

// A mirror sphere under a sky of fine checks (32 × 16 cells, 10:1): each pixel covers many
// checks near the rim, and shows their mean, not the one its centre's mirror direction hits.
// The reference: the G-buffer at 8 × 8 the resolution, each fine pixel's mirror direction
// read from the sky, averaged over the pixel. Filtered over the footprint, the absolute error
// over the covered pixels (the checks are 0.1 and 1) is under 0.6 of reading the sky at the
// centre's direction, in the mean and at the 95th percentile (measured 0.106 and 0.229
// against 0.238 and 0.487).
TEST(EnvironmentReflections, AMirrorShowsTheSkyFilteredOverItsPixel) {
    const Scene scene = mirrorSphere();
    const Camera camera = mirrorSphereCamera();
    EnvironmentImage env;
    env.width = 1024;
    env.height = 512;
    env.rgb.resize(size_t(1024) * 512 * 3);
    for (int y = 0; y < 512; ++y)
        for (int x = 0; x < 1024; ++x)
            for (int c = 0; c < 3; ++c)
                env.rgb[3 * (size_t(y) * 1024 + size_t(x)) + size_t(c)] =
                    ((x / 32 + y / 32) % 2) ? 1.0f : 0.1f;
    IblBakeParams bake;
    bake.sunThreshold = 0.0f;
    auto ibl = std::make_shared<Ibl>();
    std::string error;
    ASSERT_TRUE(bakeIbl(env, bake, *ibl, error)) << error;
    Light sky;
    sky.type = LightType::Environment;
    sky.ibl = ibl;
    constexpr int W = 48, S = 8;
    const ImageBuf gbuf = gbufferOf(scene, camera, W, W);
    const ImageBuf fine = gbufferOf(scene, camera, W * S, W * S);
    const ImageBuf lit = shade(gbuf, {sky}, nullptr);
    GBufferPixels g, f;
    ImageBuf errors;
    ASSERT_TRUE(openGBuffer(gbuf, g, errors));
    ASSERT_TRUE(openGBuffer(fine, f, errors));
    const GBufferView view(*g.pixels, g.layout, g.camera), fineView(*f.pixels, f.layout, f.camera);
    std::vector<double> filtered, point;
    for (int y = 0; y < W; ++y)
        for (int x = 0; x < W; ++x) {
            double sum = 0.0;
            bool covered = view.samples(x, y) > 0;
            for (int j = 0; j < S && covered; ++j)
                for (int i = 0; i < S && covered; ++i) {
                    if (fineView.samples(x * S + i, y * S + j) == 0) {
                        covered = false;
                        break;
                    }
                    const ShadingPoint q = fineView.at(x * S + i, y * S + j);
                    sum += env.radiance(glm::reflect(-q.V, q.N)).g;
                }
            if (!covered) continue;
            const ShadingPoint p = view.at(x, y);
            // The lobe's albedo (a white mirror: the DFG's y at N·V, about 1).
            const float albedo = ibl->dfgAt(std::max(glm::dot(p.N, p.V), 1e-4f), 0.0f).y;
            const double reference = sum / (S * S) * albedo;
            filtered.push_back(std::abs(px(lit, x, y)[1] - reference));
            point.push_back(std::abs(env.radiance(glm::reflect(-p.V, p.N)).g * albedo - reference));
        }
    ASSERT_GT(filtered.size(), 800u);
    auto stats = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        double mean = 0.0;
        for (double e : v)
            mean += e;
        return std::pair<double, double>(mean / double(v.size()), v[v.size() * 95 / 100]);
    };
    const auto [filteredMean, filteredP95] = stats(filtered);
    const auto [pointMean, pointP95] = stats(point);
    std::printf("mirror against the supersampled sky: filtered mean %.3f p95 %.3f, point mean "
                "%.3f p95 %.3f\n",
                filteredMean, filteredP95, pointMean, pointP95);
    EXPECT_LT(filteredP95, 0.6 * pointP95);
    EXPECT_LT(filteredMean, 0.6 * pointMean);
}

// A sun of 0.53° on a mirror sphere covers a hundredth of the pixel whose footprint holds its
// reflection: read at each pixel's centre it is missed (or, where a centre happens to reflect
// it, lands in one pixel a hundred times too bright). Filtered over the footprint
// (shadePunctual's spread) it is spread round its reflection with its energy. The reference:
// the G-buffer at 8 × 8 the resolution (whose footprints are near the disk's size), shaded and
// averaged over each pixel. The image's total within 15 % of the reference's, the highlight's
// centroid within a pixel of the reference's, 80 % of it within 2 pixels of that (measured:
// −12 %, 0.34 pixel, 0.90 pixel against the reference's 0.76; the centres' reading: 0.05 % of
// the total).
TEST(EnvironmentReflections, AMirrorShowsTheSunFilteredOverItsPixel) {
    const Scene scene = mirrorSphere();
    const Camera camera = mirrorSphereCamera();
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = -glm::normalize(glm::vec3(0.3f, 0.6f, 1.0f));
    sun.angle = glm::radians(0.53f);
    sun.intensity = 1.0f;
    constexpr int W = 48, S = 8;
    const ImageBuf gbuf = gbufferOf(scene, camera, W, W);
    const ImageBuf fine = gbufferOf(scene, camera, W * S, W * S);
    const ImageBuf lit = shade(gbuf, {sun}, nullptr), fineLit = shade(fine, {sun}, nullptr);
    GBufferPixels g;
    ImageBuf errors;
    ASSERT_TRUE(openGBuffer(gbuf, g, errors));
    const GBufferView view(*g.pixels, g.layout, g.camera);
    // Per image: the total, the centroid and how far from it 80 % of the green channel lies.
    struct Moments {
        double total = 0.0, x = 0.0, y = 0.0;
        void add(int px_, int py_, double v) {
            values.push_back({px_, py_, v});
            total += v;
            x += v * px_;
            y += v * py_;
        }
        std::vector<glm::dvec3> values; // x, y, value
        glm::dvec2 centre() const { return {x / total, y / total}; }
        // The radius about the centroid that holds 80 % of the total.
        double radius80() const {
            const glm::dvec2 c = centre();
            std::vector<std::pair<double, double>> d;
            for (const glm::dvec3& v : values)
                d.push_back({std::hypot(v.x - c.x, v.y - c.y), v.z});
            std::sort(d.begin(), d.end());
            double sum = 0.0;
            for (const auto& [r, v] : d)
                if ((sum += v) >= 0.8 * total) return r;
            return INFINITY;
        }
    } filtered, reference;
    double pointTotal = 0.0;
    for (int y = 0; y < W; ++y)
        for (int x = 0; x < W; ++x) {
            double r = 0.0;
            for (int j = 0; j < S; ++j)
                for (int i = 0; i < S; ++i)
                    r += px(fineLit, x * S + i, y * S + j)[1];
            reference.add(x, y, r / (S * S));
            filtered.add(x, y, px(lit, x, y)[1]);
            if (view.samples(x, y) > 0) {
                const ShadingPoint p = view.at(x, y);
                pointTotal += shadeLight(sun, p.surface, p.P, p.N, p.V).g;
            }
        }
    const double offset = glm::length(filtered.centre() - reference.centre());
    std::printf("a sun on a mirror against the supersampled one: total %.3f against %.3f (the "
                "centres' reading %.3f); centroid %.2f px apart; 80 %% within %.2f px against "
                "%.2f\n",
                filtered.total, reference.total, pointTotal, offset, filtered.radius80(),
                reference.radius80());
    EXPECT_NEAR(filtered.total / reference.total, 1.0, 0.15);
    EXPECT_LT(offset, 1.0);
    EXPECT_LT(filtered.radius80(), 2.0);
    EXPECT_LT(pointTotal, 0.1 * reference.total); // what the filter is for
}

TEST(ShadowCatcher, WithNoObjectsTheCatcherIsClear) {
    Scene scene = emptyScene();
    addGroundPlane(scene, 0.0f);
    Light light;
    light.type = LightType::Environment;
    light.ibl = sunOnlyEnvironment(glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f)));
    ImageBuf gbuf;
    const ImageBuf lit = catcherFrame(scene, light, gbuf);
    int catcher = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) {
            if (!(px(gbuf, x, y)[gbuf.spec().channelindex("A")] > 0.0f)) continue;
            ++catcher;
            ASSERT_EQ(px(lit, x, y)[3], 0.0f);
            ASSERT_EQ(px(lit, x, y)[0], 0.0f);
        }
    EXPECT_GT(catcher, 10000);
}

// A sphere over the ground plane under an environment that is one sun: the catcher's alpha is
// exactly 1 where the way to the sun passes through the sphere (shrunk by the sun's penumbra
// and the facets' sag) and exactly 0 where it misses it.
TEST(ShadowCatcher, SphereShadowMatchesItsAnalyticProjection) {
    Scene scene = emptyScene();
    const glm::vec3 centre(0.0f, 0.6f, 0.0f);
    const float radius = 0.3f;
    addSphere(scene, centre, radius, 96);
    addGroundPlane(scene, 0.0f);
    const glm::vec3 sun = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
    Light light;
    light.type = LightType::Environment;
    light.ibl = sunOnlyEnvironment(sun);
    const glm::dvec3 d(sunCentre(sun));
    ImageBuf gbuf;
    const ImageBuf lit = catcherFrame(scene, light, gbuf);
    const int catcherId = gbuf.spec().get_int_attribute("dhdr:shadowCatcher");
    ASSERT_GT(catcherId, 0);
    int inside = 0, outside = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) {
            const glm::dvec3 P(positionAt(gbuf, x, y));
            if (!(px(gbuf, x, y)[gbuf.spec().channelindex("A")] > 0.0f) || std::abs(P.y) > 1e-9)
                continue;
            // Distance from the sphere's centre to the line P + t d.
            const glm::dvec3 c = glm::dvec3(centre) - P;
            const double miss = glm::length(c - glm::dot(c, d) * d);
            const float a = px(lit, x, y)[3];
            ASSERT_EQ(px(lit, x, y)[0], 0.0f);
            if (miss < radius - 0.03) {
                ++inside;
                ASSERT_EQ(a, 1.0f) << x << "," << y;
            } else if (miss > radius + 0.03) {
                ++outside;
                ASSERT_EQ(a, 0.0f) << x << "," << y;
            }
        }
    EXPECT_GT(inside, 100);
    EXPECT_GT(outside, 5000);
}

// The light objects bounce onto the catcher, against the view factor of a glowing wall: the
// G-buffer holds only the ground plane (seen from straight above), and the lighting scene a
// roof at height H that hides the sun and a wall at x = d of radiance Le beneath it, both
// 2 km long. A floor point at x sees the wall over the view factor of a differential
// horizontal area to an infinitely long strip, F = ½ (1 − (d − x) / √((d − x)² + H²)), so it
// receives E = π Le F and reflects the luminance ρ Le F (ρ: the diffuse albedo of the plane's
// white 0.8, multiple_scattering.h), and its alpha is 1 − ρ Le F / L_open (L_open: the sun
// unshadowed, shadeLight). Without the bounce alpha is 1.
TEST(ShadowCatcher, CountsTheLightAGlowingWallBouncesOntoIt) {
    Scene floor = emptyScene();
    addGroundPlane(floor, 0.0f);
    const glm::dvec3 eye(0.0, 5.0, 0.0);
    const Camera camera = Camera::lookAt(eye, {0.0, 0.0, 0.0}, {0, 0, -1}, 0.5);
    const ImageBuf gbuf = gbufferOf(floor, camera, 64, 64);
    const float d = 1.5f, H = 1.0f, Z = 1000.0f, Le = 0.5f;
    Scene room = emptyScene();
    Material glow = room.materials[0];
    glow.name = "glow";
    glow.emission = glm::vec3(Le);
    room.materials.push_back(glow);
    addQuad(room, {-Z, H, -Z}, {Z, H, -Z}, {Z, H, Z}, {-Z, H, Z});
    addQuad(room, {d, 0, -Z}, {d, 0, Z}, {d, H, Z}, {d, H, -Z}, 1); // facing −x
    const RayCaster caster(room);
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    PbrSurface white;
    white.baseColor = glm::vec3(0.8f);
    auto run = [&](int samples, bool denoise) {
        LightingParams p;
        p.catcherBounceSamples = samples;
        p.denoise = denoise;
        ImageBuf out;
        LightingInputs inputs{{sun}, &caster};
        inputs.scene = &caster;
        EXPECT_TRUE(shadeGBuffer(out, gbuf, inputs, p)) << out.geterror();
        return out;
    };
    auto errors = [&](const ImageBuf& lit) {
        double sum = 0.0, worst = 0.0;
        int n = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                const glm::vec3 P = positionAt(gbuf, x, y);
                const glm::vec3 V = glm::normalize(glm::vec3(eye) - P);
                const float open =
                    luminance(shadeLight(sun, white, P, glm::vec3(0.0f, 1.0f, 0.0f), V));
                const double along = double(d) - P.x;
                const double F = 0.5 * (1.0 - along / std::sqrt(along * along + H * H));
                const double albedo =
                    luminance(diffuseAlbedo(white, glm::dot(glm::vec3(0.0f, 1.0f, 0.0f), V)));
                const double expected = 1.0 - albedo * Le * F / open;
                const double e = std::abs(px(lit, x, y)[3] - expected);
                sum += e;
                worst = std::max(worst, e);
                ++n;
            }
        return std::make_pair(sum / n, worst);
    };
    const ImageBuf none = run(0, true);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            ASSERT_EQ(px(none, x, y)[3], 1.0f);
    const auto [exactMean, exactWorst] = errors(run(256, false));
    const auto [defaultMean, defaultWorst] =
        errors(run(LightingParams{}.catcherBounceSamples, true));
    std::printf("catcher alpha against the view factor: 256 rays per pixel mean %.4f max %.4f; "
                "16 rays denoised mean %.4f max %.4f\n",
                exactMean, exactWorst, defaultMean, defaultWorst);
    EXPECT_LT(exactMean, 0.01);
    EXPECT_LT(exactWorst, 0.05);
    EXPECT_LT(defaultMean, 0.02);
    // In strips of 20 rows handing their estimates on (dhdr-light's way): the whole frame's
    // bits, and its bounce rays each traced once.
    LightingParams p;
    LightingInputs inputs{{sun}, &caster};
    inputs.scene = &caster;
    LightingStats wholeStats, stripStats;
    ImageBuf whole;
    ASSERT_TRUE(shadeGBuffer(whole, gbuf, inputs, p, {}, 2, &wholeStats)) << whole.geterror();
    EstimateCarry carry;
    const ImageBuf strips = shadeInStrips(gbuf, inputs, p, 20, &carry, stripStats);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            ASSERT_EQ(px(strips, x, y)[3], px(whole, x, y)[3]) << x << "," << y;
    EXPECT_GT(wholeStats.bounceRays, 10000);
    EXPECT_EQ(stripStats.bounceRays, wholeStats.bounceRays);
}

// The bounce light that BounceLighting gathers from a small glowing box floating over a floor,
// against Lambert's closed form for the irradiance of polygons (Arvo 1995: E = Le Σ_faces
// |Σ_i Θ_i N·Γ_i| / 2, Θ_i the angle between the directions to vertices i and i+1, Γ_i their
// normalised cross product) over the faces that face the point. Most floor points are far from
// the box, so most of their rays miss the sphere about the scene's triangles and are not traced:
// the skipped rays must be only rays that would have missed. Per point within 4 standard
// errors of the estimate (a hit share of F of n rays: π Le √(F (1 − F) / n)), the mean within
// 1 %, and fewer than a third of the rays traced.
TEST(ShadowCatcher, BounceLightOfASmallGlowingBoxIsLambertsPolygonFormula) {
    const float Le = 0.5f;
    const glm::vec3 lo(0.3f, 0.4f, -0.15f), hi(0.6f, 0.7f, 0.15f);
    Scene box = emptyScene();
    Material glow = box.materials[0];
    glow.name = "glow";
    glow.baseColor = glm::vec3(0.0f);
    glow.emission = glm::vec3(Le);
    box.materials.push_back(glow);
    addBox(box, lo, hi, 1);
    const RayCaster caster(box);
    const std::vector<Light> none;
    const DirectLighting direct(none, DirectLightingOptions{});
    const HitShading hits(caster, direct, nullptr, true, kHitMinRoughness, DiffuseModel::Lambert);
    const BounceLighting bounce(hits);
    const glm::vec3 up(0.0f, 1.0f, 0.0f);
    const int n = 1024;
    long long rays = 0;
    double sumEstimate = 0.0, sumExact = 0.0;
    int points = 0;
    for (float z = -2.0f; z <= 2.0f; z += 0.25f)
        for (float x = -2.0f; x <= 2.0f; x += 0.25f) {
            const glm::vec3 P(x, 0.0f, z);
            double E = 0.0;
            for (const Mesh& face : box.meshes) {
                const glm::dvec3 normal(face.normals[0]);
                if (glm::dot(normal, glm::dvec3(P) - glm::dvec3(face.positions[0])) <= 0.0)
                    continue;
                double f = 0.0;
                for (size_t i = 0; i < 4; ++i) {
                    const glm::dvec3 a =
                        glm::normalize(glm::dvec3(face.positions[i]) - glm::dvec3(P));
                    const glm::dvec3 b =
                        glm::normalize(glm::dvec3(face.positions[(i + 1) % 4]) - glm::dvec3(P));
                    f += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) *
                         glm::dot(glm::dvec3(up), glm::normalize(glm::cross(a, b)));
                }
                E += double(Le) * std::abs(f) / 2.0;
            }
            const glm::vec3 estimate =
                bounce.irradiance(SurfacePoint{P, up, 1e-6f}, up,
                                  sampleSeed(int(x * 4), int(z * 4), -2), 7, n, &rays);
            const double F = E / (kPi * Le);
            const double standardError = kPi * Le * std::sqrt(F * (1.0 - F) / n);
            EXPECT_NEAR(estimate.r, E, 4.0 * standardError + 1e-6) << x << "," << z;
            sumEstimate += estimate.r;
            sumExact += E;
            ++points;
        }
    std::printf("bounce off a glowing box: mean %.5f against %.5f; %lld of %d rays traced\n",
                sumEstimate / points, sumExact / points, rays, points * n);
    EXPECT_NEAR(sumEstimate / sumExact, 1.0, 0.01);
    EXPECT_LT(rays, (long long)points * n / 3);
}

// The directions BounceLighting does not trace (outside the spheres round its meshes) must be
// only directions that miss: its estimate against every one of the same rays traced, the
// same bits. Three glowing boxes apart over a floor, lit by a point light, at points between
// and under them (inside a box's sphere nothing is culled), on a grazing floor normal too.
TEST(ShadowCatcher, BounceLightCullsOnlyRaysThatMiss) {
    Scene scene = emptyScene();
    Material glow = scene.materials[0];
    glow.name = "glow";
    glow.emission = glm::vec3(0.3f, 0.5f, 0.7f);
    scene.materials.push_back(glow);
    addBox(scene, {-1.2f, 0.2f, -0.2f}, {-0.8f, 0.6f, 0.2f}, 1);
    addBox(scene, {0.1f, 0.05f, 0.9f}, {0.3f, 1.5f, 1.1f}, 0);
    addBox(scene, {1.0f, 0.4f, -1.3f}, {1.6f, 0.5f, -0.7f}, 1);
    const RayCaster caster(scene);
    std::vector<Light> lights(1);
    lights[0].type = LightType::Point;
    lights[0].position = glm::vec3(0.0f, 3.0f, 0.0f);
    lights[0].intensity = 20.0f;
    const DirectLighting direct(lights, DirectLightingOptions{&caster});
    const HitShading hits(caster, direct, nullptr, true, kHitMinRoughness, DiffuseModel::Lambert);
    const BounceLighting bounce(hits);
    const int n = 64;
    long long culled = 0, all = 0;
    int lit = 0;
    for (float z = -2.0f; z <= 2.0f; z += 0.2f)
        for (float x = -2.0f; x <= 2.0f; x += 0.2f) {
            const glm::vec3 P(x, 0.0f, z);
            const glm::vec3 N = glm::normalize(glm::vec3(x > 0.0f ? 0.9f : 0.0f, 1.0f, 0.0f));
            const SurfacePoint at{P, glm::vec3(0.0f, 1.0f, 0.0f), 1e-6f};
            const std::uint64_t directions = sampleSeed(int(x * 5), int(z * 5), -2);
            const glm::vec3 fast = bounce.irradiance(at, N, directions, 7, n, &culled);
            glm::vec3 t, b;
            orthonormalBasis(N, t, b);
            const RotatedHammersley sequence(directions);
            glm::dvec3 sum(0.0);
            for (int i = 0; i < n; ++i) {
                const glm::vec3 h = cosineHemisphere(sequence(std::uint32_t(i), std::uint32_t(n)));
                const glm::vec3 wi = glm::normalize(h.x * t + h.y * b + h.z * N);
                if (!(glm::dot(at.Ng, wi) > 0.0f)) continue;
                sum += glm::dvec3(hits.trace({glm::dvec3(offsetRayOrigin(at, wi)), glm::dvec3(wi)},
                                             SeedKey{7, i, streamOf(SampleStream::BounceShadow)},
                                             &all));
            }
            const glm::vec3 reference(sum * (3.14159265358979323846 / double(n)));
            for (int c = 0; c < 3; ++c)
                EXPECT_EQ(fast[c], reference[c]) << x << "," << z << " channel " << c;
            lit += reference.g > 0.0f;
        }
    std::printf("bounce light: %lld of %lld rays traced, %d points lit\n", culled, all, lit);
    EXPECT_GT(lit, 100);
    EXPECT_LT(culled, all / 2);
}

namespace {

// Brute force: Σ Y(L) cos θ Ω V / Σ Y(L) cos θ Ω over the texels of the environment's
// sampling table, each texel's centre traced, in double.
double bruteForceVisibility(const Light& light, const SurfacePoint& at, const glm::vec3& N,
                            const Visibility& caster) {
    const EnvironmentSampler& table = light.ibl->sampler;
    double seen = 0.0, total = 0.0;
    for (int y = 0; y < table.height; ++y) {
        const double omega = 2.0 * kPi / table.width *
                             (double(table.rowCos[size_t(y)]) - table.rowCos[size_t(y) + 1]);
        for (int x = 0; x < table.width; ++x) {
            const glm::vec3 d = equirectDirection(
                {(float(x) + 0.5f) / float(table.width), (float(y) + 0.5f) / float(table.height)});
            const double cosTheta = glm::dot(N, d);
            if (!(cosTheta > 0.0)) continue;
            const glm::vec3 L = table.texels[size_t(y) * size_t(table.width) + size_t(x)].radiance;
            const double w = (0.2126 * L.r + 0.7152 * L.g + 0.0722 * L.b) * cosTheta * omega;
            const ShadowRay ray{offsetRayOrigin(at, d), d, INFINITY};
            total += w;
            seen += w * caster.transmittance(ray);
        }
    }
    return seen / total;
}

} // namespace

// The environment's visibility on floor points around a box, under a sky with a sun, against
// the brute-force ratio in double over every texel of the sampler's table (its centre's ray
// traced): the mean agrees, the error falls as the samples grow (each 4× more samples at
// least 1.4× less RMS error against a 4096-sample estimate: the sequences are decorrelated
// per sample, not only per pixel), and no point that sees sky is exactly black.
TEST(EnvironmentShadows, MoreSamplesMeanLessNoiseAndTheMeanIsTheBruteForceRatio) {
    Scene scene = emptyScene();
    addFloor(scene, 3.0f);
    addBox(scene, {-0.3f, 0.0f, -0.3f}, {0.3f, 0.9f, 0.3f});
    const RayCaster caster(scene);
    Light light;
    light.type = LightType::Environment;
    light.ibl = skyWithSun(glm::normalize(glm::vec3(0.5f, 1.0f, 0.2f)), 1.0f);
    const glm::vec3 up(0.0f, 1.0f, 0.0f);
    std::vector<SurfacePoint> points;
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 20; ++j) {
            const glm::vec3 P(-1.2f + 0.1f * float(i), 0.0f, -1.2f + 0.1f * float(j));
            if (std::abs(P.x) < 0.35f && std::abs(P.z) < 0.35f) continue; // under the box
            points.push_back({P, up, 1e-5f});
        }
    std::vector<double> exact;
    for (const SurfacePoint& at : points)
        exact.push_back(bruteForceVisibility(light, at, up, caster));
    auto estimate = [&](int samples) {
        std::vector<double> v;
        for (size_t k = 0; k < points.size(); ++k)
            v.push_back(lightVisibility(light, points[k], up, sampleSeed(int(k), 7, 0, 1), samples,
                                        caster));
        return v;
    };
    const std::vector<double> reference = estimate(4096);
    double previous = 0.0;
    for (int samples : {16, 64, 256}) {
        SCOPED_TRACE(std::to_string(samples) + " samples");
        const std::vector<double> v = estimate(samples);
        double sum = 0.0, sumExact = 0.0, squared = 0.0;
        int black = 0, shaded = 0;
        for (size_t k = 0; k < v.size(); ++k) {
            sum += v[k];
            sumExact += exact[k];
            squared += (v[k] - reference[k]) * (v[k] - reference[k]);
            black += exact[k] > 0.1 && v[k] == 0.0;
            shaded += exact[k] < 0.9;
        }
        const double n = double(v.size()), rms = std::sqrt(squared / n);
        EXPECT_NEAR(sum / n, sumExact / n, 0.02);
        EXPECT_EQ(black, 0);
        EXPECT_GT(shaded, 20);
        if (previous > 0.0) {
            EXPECT_LT(rms, previous / 1.4);
        }
        std::printf("%d samples: RMS %.4f, mean %.4f (brute force %.4f)\n", samples, rms, sum / n,
                    sumExact / n);
        previous = rms;
    }
}

namespace {

// The environment's visibility at `at` for the diffuse (lobe null) or the glossy lobe, by
// quadrature over a 512 × 256 grid of directions (each cell's centre traced), in double:
// Σ w cos θ Ω (V Y(L) + (1 − V) Y(occluder)) / Σ Y(L) w cos θ Ω, w = D · Vis for the lobe
// (whose occluder is grey, ρ E(−l) / π), 1 for the diffuse (no occluder light).
double bruteForceLobeVisibility(const Light& light, const SurfacePoint& at, const glm::vec3& N,
                                const SpecularLobe* lobe, const Visibility& caster) {
    constexpr int W = 512, H = 256;
    double seen = 0.0, total = 0.0;
    for (int y = 0; y < H; ++y) {
        const double omega =
            2.0 * kPi / W * (std::cos(kPi * double(y) / H) - std::cos(kPi * double(y + 1) / H));
        for (int x = 0; x < W; ++x) {
            const glm::vec3 d =
                equirectDirection({(float(x) + 0.5f) / float(W), (float(y) + 0.5f) / float(H)});
            const float cosTheta = glm::dot(N, d);
            if (!(cosTheta > 0.0f)) continue;
            double w = cosTheta * omega;
            if (lobe) { // D · Vis
                const float NdotV = glm::dot(N, lobe->V);
                const glm::vec3 h = glm::normalize(d + lobe->V);
                w *= double(ggxDistribution(std::max(glm::dot(N, h), 0.0f), lobe->alpha) *
                            smithGgxCorrelatedVisibility(cosTheta, NdotV, lobe->alpha));
            }
            const glm::vec3 L = environmentRadiance(light, d);
            const double y = 0.2126 * L.r + 0.7152 * L.g + 0.0722 * L.b;
            if (!(w * y > 0.0)) continue;
            total += w * y;
            const double v = caster.transmittance({offsetRayOrigin(at, d), d, INFINITY});
            // A blocked direction: a grey occluder lit by the sky's irradiance facing back.
            const glm::vec3 E = light.ibl->irradiance(-d);
            const double fill =
                lobe ? lobe->occluderAlbedo / kPi * (0.2126 * E.r + 0.7152 * E.g + 0.0722 * E.b)
                     : 0.0;
            seen += w * (v * y + (1.0 - v) * fill);
        }
    }
    return seen / total;
}

} // namespace

// A glossy floor in front of a wall that its mirror direction meets: the wall hides most of
// the glossy lobe but little of the sky, so the environment's specular light must be
// shadowed by its own ratio (BRDF-weighted, from GGX samples among the rest), not by the
// diffuse one. Both ratios agree with the quadrature (mean over the points within 0.03 at
// 256 samples), and the specular one is well below the diffuse one; with the grey occluder
// of the default lobe, the wall's part of the reflection is that grey surface's light.
TEST(EnvironmentShadows, GlossyLightIsShadowedByWhatItsLobeSees) {
    Scene scene = emptyScene();
    addFloor(scene, 10.0f);
    addBox(scene, {0.0f, 0.0f, -3.0f}, {0.2f, 1.5f, 3.0f});
    const RayCaster caster(scene);
    Light light;
    light.type = LightType::Environment;
    light.ibl = skyWithSun(glm::normalize(glm::vec3(-0.5f, 1.0f, 0.3f)), 1.0f);
    const glm::vec3 up(0.0f, 1.0f, 0.0f);
    // Seen from far off on the −X side, 45° above the floor: the mirror direction climbs
    // towards +X into the wall.
    const SpecularLobe lobe{glm::normalize(glm::vec3(-1.0f, 1.0f, 0.0f)), 0.25f * 0.25f, 0.0f};
    SpecularLobe grey = lobe;
    grey.occluderAlbedo = kOccluderAlbedo;
    double diffuse = 0.0, specular = 0.0, exactDiffuse = 0.0, exactSpecular = 0.0,
           withOccluder = 0.0, exactWithOccluder = 0.0;
    int n = 0;
    for (int i = 0; i < 5; ++i) {
        const SurfacePoint at{glm::vec3(-0.9f + 0.15f * float(i), 0.0f, 0.1f * float(i)), up,
                              1e-5f};
        const EnvironmentVisibilitySums sums =
            environmentVisibilitySums(light, at, up, &lobe, sampleSeed(i, 5, 0, 1), 256, caster);
        const EnvironmentVisibility v = ratios(sums);
        EXPECT_GT(sums.specular.count, 0);
        diffuse += v.diffuse;
        specular += v.specular;
        exactDiffuse += bruteForceLobeVisibility(light, at, up, nullptr, caster);
        exactSpecular += bruteForceLobeVisibility(light, at, up, &lobe, caster);
        withOccluder += ratios(environmentVisibilitySums(light, at, up, &grey,
                                                         sampleSeed(i, 5, 0, 1), 256, caster))
                            .specular;
        exactWithOccluder += bruteForceLobeVisibility(light, at, up, &grey, caster);
        ++n;
    }
    diffuse /= n;
    specular /= n;
    exactDiffuse /= n;
    exactSpecular /= n;
    std::printf("diffuse %.4f (quadrature %.4f), specular %.4f (quadrature %.4f)\n", diffuse,
                exactDiffuse, specular, exactSpecular);
    EXPECT_NEAR(diffuse, exactDiffuse, 0.03);
    EXPECT_NEAR(specular, exactSpecular, 0.03);
    EXPECT_LT(exactSpecular, 0.5 * exactDiffuse);
    // With the grey occluder the blocked part of the reflection is not black.
    withOccluder /= n;
    exactWithOccluder /= n;
    std::printf("specular with a grey occluder %.4f (quadrature %.4f)\n", withOccluder,
                exactWithOccluder);
    EXPECT_NEAR(withOccluder, exactWithOccluder, 0.03);
    EXPECT_GT(exactWithOccluder, exactSpecular + 0.1);
}

// A wall facing away from a sun that holds almost all of the sky's light, the floor hiding the
// lower half of its hemisphere: drawn by luminance alone, nearly every sample goes to the sun
// below the wall's horizon, and the one or two left above it decide the pixel (black when
// the floor blocks them). With the cosine-weighted half of the samples, no point is black at
// any sample count and the mean is the brute-force ratio.
TEST(EnvironmentShadows, ASurfaceFacingAwayFromTheSunIsNeverBlack) {
    Scene scene = emptyScene();
    addFloor(scene, 50.0f);
    const RayCaster caster(scene);
    Light light;
    light.type = LightType::Environment;
    light.ibl = skyWithSun(glm::normalize(glm::vec3(1.0f, 0.6f, 0.1f)), 0.02f);
    const glm::vec3 N(-1.0f, 0.0f, 0.0f);
    std::vector<SurfacePoint> points;
    for (int i = 0; i < 100; ++i)
        points.push_back({{0.0f, 0.01f + 0.002f * float(i), 0.05f * float(i)}, N, 1e-5f});
    double exact = 0.0;
    for (const SurfacePoint& at : points)
        exact += bruteForceVisibility(light, at, N, caster);
    exact /= double(points.size());
    ASSERT_GT(exact, 0.3);
    for (int samples : {1, 4, 16, 64}) {
        SCOPED_TRACE(std::to_string(samples) + " samples");
        double sum = 0.0;
        int black = 0;
        for (size_t k = 0; k < points.size(); ++k) {
            const float v =
                lightVisibility(light, points[k], N, sampleSeed(int(k), 3, 0, 1), samples, caster);
            black += v == 0.0f;
            sum += v;
        }
        if (samples >= 4) {
            EXPECT_EQ(black, 0);
        }
        if (samples >= 16) {
            EXPECT_NEAR(sum / double(points.size()), exact, 0.05);
        }
    }
}

// A sun of 4° over the edge of a roof: on the floor 1 m below, the visible share of its disk
// is the closed form of a circle cut by a chord (the roof's edge) at the angle atan(x) from
// its centre, within the Monte Carlo error of 256 stratified rays; beyond the penumbra the
// floor is exactly lit or exactly dark.
TEST(Shadows, ASunWithAnAngleCastsTheDisksPenumbra) {
    Scene scene = emptyScene();
    addQuad(scene, {-50, 1, -50}, {-50, 1, 50}, {0, 1, 50}, {0, 1, -50});
    const RayCaster caster(scene);
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = {0.0f, -1.0f, 0.0f};
    sun.angle = 4.0f * kPi / 180.0f;
    const double r = 0.5 * double(sun.angle);
    // The share of a disk of radius r beyond a chord at distance d from its centre.
    auto beyond = [&](double d) {
        if (d >= r) return 0.0;
        if (d <= -r) return 1.0;
        const double c = (r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d)) / (kPi * r * r);
        return c;
    };
    const glm::vec3 up(0.0f, 1.0f, 0.0f);
    int penumbra = 0;
    for (int i = -60; i <= 60; ++i) {
        const float x = 0.001f * float(i);
        const SurfacePoint at{{x, 0.0f, 0.3f}, up, 1e-6f};
        const float v = lightVisibility(sun, at, up, sampleSeed(i, 11, 0, 1), 256, caster);
        // Blocked where the ray's slope d.x / d.y < −x: the disk's part beyond the chord at
        // atan(x) on the roof's side.
        const double exact = 1.0 - beyond(std::atan(double(x)));
        SCOPED_TRACE("x = " + std::to_string(x));
        if (std::abs(std::atan(double(x))) > r + 1e-4) {
            EXPECT_EQ(v, exact > 0.5 ? 1.0f : 0.0f);
        } else {
            EXPECT_NEAR(v, exact, 0.03);
            ++penumbra;
        }
    }
    EXPECT_GT(penumbra, 60);

    // (256 samples trace every ray.) At 16 samples four first rays near the disk's rim decide
    // the points where all four agree (shadows.cpp). Against all 16 traced and weighted here:
    // the same value wherever the first rays disagree; elsewhere exactly lit or dark, and
    // rarely unlike the 16 rays (a sliver of the disk hidden between the first four).
    int differ = 0, decided = 0;
    for (int i = -60; i <= 60; ++i) {
        const float x = 0.001f * float(i);
        const SurfacePoint at{{x, 0.0f, 0.3f}, up, 1e-6f};
        const std::uint64_t seed = sampleSeed(i, 12, 0, 1);
        long long rays = 0;
        const float v = lightVisibility(sun, at, up, seed, 16, caster, &rays);
        double total = 0.0, seen = 0.0;
        for (std::uint32_t k = 0; k < 16; ++k) {
            const LightLiSample s = sampleLi(sun, at.P, hammersley(k, 16, seed));
            const double w = double(s.L.r + s.L.g + s.L.b) * glm::dot(up, s.wi) / s.pdf;
            total += w;
            seen += w * static_cast<const Visibility&>(caster).transmittance(
                            ShadowRay{offsetRayOrigin(at, s.wi), s.wi, INFINITY});
        }
        const double full = seen / total;
        SCOPED_TRACE("x = " + std::to_string(x));
        if (rays == 4) {
            ++decided;
            EXPECT_TRUE(v == 0.0f || v == 1.0f);
            EXPECT_LE(std::abs(v - full), 0.35);
            differ += std::abs(v - full) > 1e-6;
        } else {
            EXPECT_EQ(rays, 4 + 16);
            EXPECT_NEAR(v, full, 1e-6);
        }
    }
    // Most points are wholly lit or dark, and traced with four rays only.
    EXPECT_GT(decided, 50);
    EXPECT_LE(differ, 12);
    std::printf("16 samples: %d of 121 points decided by 4 rays, %d of them unlike all 16\n",
                decided, differ);
    // Without an angle, one ray: a hard edge.
    sun.angle = 0.0f;
    EXPECT_EQ(lightVisibility(sun, {{0.01f, 0.0f, 0.3f}, up, 1e-6f}, up, 1, 256, caster), 1.0f);
    EXPECT_EQ(lightVisibility(sun, {{-0.01f, 0.0f, 0.3f}, up, 1e-6f}, up, 1, 256, caster), 0.0f);
}

// Coherent packets (rtcOccluded4/8/16) answer as single rays do: a box in a room, rays from a
// grid of points on its floor towards a point light, in tile order and one at a time.
TEST(Occlusion, CoherentPacketsAnswerAsSingleRays) {
    Scene scene = emptyScene();
    addFloor(scene, 2.0f);
    addBox(scene, {-0.3f, 0.0f, -0.3f}, {0.3f, 0.6f, 0.3f});
    const RayCaster caster(scene);
    const glm::vec3 light(0.2f, 1.5f, 0.1f), up(0.0f, 1.0f, 0.0f);
    std::vector<ShadowRay> rays;
    for (int ty = 0; ty < 64; ty += 16)
        for (int tx = 0; tx < 64; tx += 16)
            for (int y = ty; y < ty + 16; ++y)
                for (int x = tx; x < tx + 16; ++x) {
                    const SurfacePoint at{
                        {-1.5f + 3.0f * x / 63.0f, 0.0f, -1.5f + 3.0f * y / 63.0f}, up, 1e-6f};
                    const glm::vec3 to = light - at.P;
                    rays.push_back({offsetRayOrigin(at, glm::normalize(to)), glm::normalize(to),
                                    glm::length(to)});
                }
    rays.resize(rays.size() - 5); // a last packet that is not full
    std::vector<float> packets(rays.size());
    caster.testCoherent(rays.data(), rays.size(), packets.data());
    // And in calls of 1–16 rays: packets of 4, 8 and 16, full or not (a sun's first 4 rays).
    std::vector<float> small(rays.size());
    for (size_t begin = 0, k = 0; begin < rays.size(); ++k) {
        const size_t n = std::min(1 + k % 16, rays.size() - begin);
        caster.testCoherent(rays.data() + begin, n, small.data() + begin);
        begin += n;
    }
    ASSERT_EQ(small, packets);
    int blocked = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(packets[i], caster.transmittance(rays[i].origin, rays[i].direction, rays[i].tmax))
            << i;
        blocked += packets[i] == 0.0f;
    }
    EXPECT_GT(blocked, 100);
    EXPECT_LT(blocked, int(rays.size()) - 100);
}

// A cone that RayCaster::mayBlockCone calls unblockable has only open rays: cones of 0.5–10°
// from points around and inside two boxes over a ground plane, each checked with 64 rays from
// within its radius of the apex in directions across it (its rim included); and it clears
// most cones from points that look away, so that suns skip their rays there.
TEST(Occlusion, AConeThatCannotBeBlockedHasOnlyOpenRays) {
    Scene scene = emptyScene();
    addBox(scene, {-0.5f, 0.0f, -0.5f}, {0.0f, 0.6f, 0.2f});
    addBox(scene, {0.4f, 0.2f, 0.1f}, {0.9f, 0.5f, 0.4f});
    scene.hasGroundPlane = true;
    scene.groundPlaneY = 0.0f;
    const RayCaster caster(scene);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    int cleared = 0, tested = 0;
    for (int i = 0; i < 3000; ++i) {
        const glm::vec3 apex(-2.0f + 4.0f * unit(rng), -0.2f + 2.0f * unit(rng),
                             -2.0f + 4.0f * unit(rng));
        const glm::vec3 axis =
            glm::normalize(glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.2f, unit(rng) - 0.5f));
        const float halfAngle = glm::radians(0.25f + 4.75f * unit(rng)),
                    radius = i % 3 == 0 ? 0.01f * unit(rng) : 0.0f;
        if (caster.mayBlockCone(apex, radius, axis, halfAngle)) continue;
        ++cleared;
        glm::vec3 t, b;
        orthonormalBasis(axis, t, b);
        for (int k = 0; k < 64; ++k) {
            const float cosMax = std::cos(halfAngle);
            const glm::vec3 c = uniformCone({unit(rng), k < 16 ? 1.0f - 1e-7f : unit(rng)}, cosMax);
            const glm::vec3 d = glm::normalize(c.x * t + c.y * b + c.z * axis);
            const glm::vec3 o =
                apex + radius * glm::normalize(glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f,
                                                         unit(rng) - 0.5f));
            ASSERT_EQ(caster.transmittance(o, d, INFINITY), 1.0f) << "cone " << i << " ray " << k;
            ++tested;
        }
    }
    EXPECT_GT(cleared, 1000);
    // Towards the boxes, or down onto the plane: may be blocked.
    EXPECT_TRUE(caster.mayBlockCone({-0.25f, 0.3f, 2.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, 0.01f));
    EXPECT_TRUE(
        caster.mayBlockCone({3.0f, 1.0f, 3.0f}, 0.0f, glm::normalize(glm::vec3(1, -1, 0)), 0.01f));
    // Just above the horizon: its rim reaches the plane only when the cone is wide.
    const glm::vec3 low = glm::normalize(glm::vec3(0.0f, 0.02f, 1.0f));
    EXPECT_FALSE(caster.mayBlockCone({0.0f, 0.5f, 3.0f}, 0.0f, low, 0.005f));
    EXPECT_TRUE(caster.mayBlockCone({0.0f, 0.5f, 3.0f}, 0.0f, low, 0.05f));
}

// Rays that miss the triangles' bounds are answered without Embree (RayCaster's cull): rays
// aimed at points on a box's faces, 10⁻⁵ inside their edges, from all around it and from
// within (the box's surface is the bounds, so these graze them), all hit it at the distance
// of the point aimed at; rays aimed 10⁻⁵ outside the box's silhouette edges, or stopped 10⁻⁵
// short of the face, do not. Closest hits (intersect), single occlusion rays, batches and
// packets alike.
TEST(Occlusion, RaysGrazingTheSceneBoundsAreStillTraced) {
    Scene scene = emptyScene();
    const glm::vec3 lo(-0.3f, 0.2f, -0.5f), hi(0.4f, 0.9f, 0.25f);
    addBox(scene, lo, hi);
    const RayCaster caster(scene);
    ASSERT_TRUE(caster.ok());
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<ShadowRay> hitting, missing;
    for (int i = 0; i < 4000; ++i) {
        // A point on face `axis` (low or high side), its other two coordinates within
        // [lo + ε, hi − ε] (ε = 10⁻⁵), and an origin outside that face's side.
        const int axis = i % 3;
        const bool high = (i / 3) % 2 != 0;
        const float e = 1e-5f;
        glm::vec3 target, origin;
        for (int c = 0; c < 3; ++c)
            target[c] = lo[c] + e + (hi[c] - lo[c] - 2.0f * e) * unit(rng);
        target[axis] = high ? hi[axis] : lo[axis];
        for (int c = 0; c < 3; ++c)
            origin[c] = target[c] + (unit(rng) - 0.5f) * 6.0f;
        origin[axis] = target[axis] + (high ? 1.0f : -1.0f) * (0.01f + 2.0f * unit(rng));
        const glm::vec3 d = glm::normalize(target - origin);
        const float t = glm::length(target - origin);
        hitting.push_back({origin, d, t * 1.001f});
        missing.push_back({origin, d, t * (1.0f - 1e-5f)});
        const RayHit h = caster.intersect({glm::dvec3(origin), glm::dvec3(d)});
        ASSERT_TRUE(h.hit) << i;
        ASSERT_NEAR(h.t, t, 1e-4 * t) << i;
        // Past a silhouette: the same origin aimed 10⁻⁵ beyond the face's edge, along a
        // direction that leaves the box's slab of the other two axes before reaching it.
        glm::vec3 beyond = target;
        const int other = (axis + 1) % 3;
        beyond[other] =
            (target[other] - lo[other] < hi[other] - target[other]) ? lo[other] - e : hi[other] + e;
        const glm::vec3 o2 = beyond + (beyond - glm::vec3(0.05f, 0.55f, -0.125f)) * 3.0f;
        const glm::vec3 d2 = glm::normalize(beyond - o2);
        missing.push_back({o2, d2, glm::length(beyond - o2)});
    }
    // From inside the box, every ray hits a face.
    for (int i = 0; i < 500; ++i) {
        const glm::vec3 o = lo + (hi - lo) * glm::vec3(unit(rng), unit(rng), unit(rng));
        const glm::vec3 d = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) - 0.5f);
        hitting.push_back({o, d, 10.0f});
        EXPECT_TRUE(caster.intersect({glm::dvec3(o), glm::dvec3(d)}).hit);
    }
    for (const std::vector<ShadowRay>* rays : {&hitting, &missing}) {
        const float expected = rays == &hitting ? 0.0f : 1.0f;
        std::vector<float> batch(rays->size()), packets(rays->size());
        caster.test(rays->data(), rays->size(), batch.data());
        caster.testCoherent(rays->data(), rays->size(), packets.data());
        for (size_t i = 0; i < rays->size(); ++i) {
            const ShadowRay& r = (*rays)[i];
            ASSERT_EQ(caster.transmittance(r.origin, r.direction, r.tmax), expected) << i;
            ASSERT_EQ(batch[i], expected) << i;
            ASSERT_EQ(packets[i], expected) << i;
        }
    }
}

// The filter's own exp against the library's in double, over the whole range it is used on.
TEST(Denoise, ExpNegativeIsExpWithinItsBound) {
    double worst = 0.0;
    for (int k = 0; k < 1000000; ++k) {
        const float x = -87.0f * float(k) / 1e6f;
        const double exact = std::exp(double(x));
        worst = std::max(worst, std::abs(double(expNegative(x)) - exact) / exact);
    }
    EXPECT_LT(worst, 3e-7);
    EXPECT_EQ(expNegative(0.0f), 1.0f);
    EXPECT_EQ(expNegative(1.0f), 1.0f);
    EXPECT_EQ(expNegative(-100.0f), 0.0f);
    EXPECT_EQ(expNegative(-std::numeric_limits<float>::infinity()), 0.0f);
}

// An estimate that exists on one object only (the specular light of a metal): filtered with
// its mask, the object's pixels get exactly what the unmasked filter gives them (other
// objects never mix with them), and the other pixels keep their values untouched.
TEST(Denoise, AMaskSkipsThePixelsWithoutTheEstimate) {
    constexpr int W = 37, H = 23; // not a multiple of the four lanes
    const size_t n = size_t(W) * H;
    DenoiseGuide guide;
    guide.width = W;
    guide.height = H;
    guide.position.resize(n);
    guide.normal.assign(n, glm::vec3(0.0f, 1.0f, 0.0f));
    guide.object.resize(n);
    guide.surface.assign(n, 1);
    std::vector<unsigned char> mask(n);
    std::vector<float> plain(n);
    for (size_t p = 0; p < n; ++p) {
        const int x = int(p % W), y = int(p / W);
        guide.position[p] = glm::vec3(0.01f * float(x), 0.0f, 0.01f * float(y));
        const bool metal = (x - 18) * (x - 18) + (y - 11) * (y - 11) < 64;
        guide.object[p] = metal ? 2.0f : 1.0f;
        mask[p] = metal;
        plain[p] = float(mixBits(p) >> 40) * 0x1p-24f + (metal ? 1.0f : 0.0f);
    }
    std::vector<float> masked = plain, unmasked = plain;
    atrousFilter({DenoiseEstimate{&masked, 1, nullptr, nullptr, &mask}}, guide);
    atrousFilter(unmasked, 1, guide);
    int changed = 0;
    for (size_t p = 0; p < n; ++p) {
        if (mask[p]) {
            ASSERT_EQ(masked[p], unmasked[p]) << p;
            changed += masked[p] != plain[p];
        } else {
            ASSERT_EQ(masked[p], plain[p]) << p;
        }
    }
    EXPECT_GT(changed, 100);
}

// A curved floor of two objects with a few pixels without a surface, 203 pixels wide (not a
// whole number of lanes): sums of varied size, a few noisy shadows, a lobe direction per pixel,
// a single value in one patch.
struct FloorEstimates {
    static constexpr int W = 203, H = 150;
    static constexpr size_t n = size_t(W) * H;
    DenoiseGuide guide;
    std::vector<glm::vec3> direction = std::vector<glm::vec3>(n);
    std::vector<float> ratio = std::vector<float>(2 * n), value = std::vector<float>(n, 0.0f);
    std::vector<float> width = std::vector<float>(n, 0.3f);
    std::vector<unsigned char> patch = std::vector<unsigned char>(n, 0);

    FloorEstimates() {
        guide.width = W;
        guide.height = H;
        guide.position.resize(n);
        guide.normal.resize(n);
        guide.object.resize(n);
        guide.surface.resize(n);
        auto noise = [](size_t p, int k) {
            return float(mixBits(p * 4 + size_t(k)) >> 40) * 0x1p-24f;
        };
        for (size_t p = 0; p < n; ++p) {
            const int x = int(p % W), y = int(p / W);
            const float u = 0.01f * float(x);
            guide.position[p] = glm::vec3(u, 0.2f * u * u, 0.01f * float(y));
            guide.normal[p] = glm::normalize(glm::vec3(-0.4f * u, 1.0f, 0.0f));
            guide.object[p] = x < 120 ? 1.0f : 2.0f;
            guide.surface[p] = (x + y) % 37 != 0; // a few pixels without a surface
            direction[p] = glm::normalize(glm::vec3(float(x - W / 2), 100.0f, float(y)));
            const float total = 0.5f + noise(p, 0);
            const bool shadowed = (x - 40) * (x - 40) + (y - 30) * (y - 30) < 100 ||
                                  (x > 150 && x < 160 && y > 110 && y < 118);
            ratio[p] = shadowed ? total * noise(p, 1) : total;
            ratio[n + p] = total;
            patch[p] = (x - 170) * (x - 170) + (y - 20) * (y - 20) < 50;
            if (patch[p]) value[p] = noise(p, 2);
        }
    }
};

// Far from any shadow a ratio estimate is settled (shadowed = unshadowed sums) and so is a
// bounce estimate of 0: the filter skips what lies beyond its reach of the unsettled pixels,
// and the ratios and values are the same bits as filtering everywhere.
TEST(Denoise, SettledNeighbourhoodsAreSkippedWithTheSameResult) {
    const FloorEstimates f;
    const size_t n = f.n;
    auto filter = [&](bool skip, std::vector<float>& r, std::vector<float>& v) {
        r = f.ratio;
        v = f.value;
        DenoiseEstimate a{&r, 2, &f.direction, &f.width}, b{&v, 1};
        a.skipSettled = b.skipSettled = skip;
        atrousFilter({a, b}, f.guide);
    };
    std::vector<float> r0, v0, r1, v1;
    filter(false, r0, v0);
    filter(true, r1, v1);
    int untouched = 0, filtered = 0;
    for (size_t p = 0; p < n; ++p) {
        if (!f.guide.surface[p]) continue;
        auto q = [&](const std::vector<float>& r) {
            return r[n + p] > 0.0f ? r[p] / r[n + p] : 1.0f;
        };
        ASSERT_EQ(q(r1), q(r0)) << p;
        ASSERT_EQ(v1[p], v0[p]) << p;
        untouched += r1[n + p] == f.ratio[n + p];
        filtered += q(r0) != 1.0f;
    }
    EXPECT_GT(untouched, int(n / 4)); // skipped
    EXPECT_GT(filtered, 1000);        // the shadows spread over their reach
}

// A strip's halo is read for its neighbours only: filtering with the wanted rows named gives
// those rows the bits of filtering every row, and leaves the others as they were.
TEST(Denoise, WantedRowsGetTheBitsOfTheWholeFilter) {
    FloorEstimates f;
    using Planes = std::vector<std::vector<float>>;
    auto filter = [&](int firstRow, int endRow) {
        f.guide.firstRow = firstRow;
        f.guide.endRow = endRow;
        Planes p{f.ratio, f.value, f.ratio};
        DenoiseEstimate a{&p[0], 2, &f.direction, &f.width},
            b{&p[1], 1, &f.direction, &f.width, &f.patch}, c{&p[2], 2};
        c.skipSettled = false;
        atrousFilter({a, b, c}, f.guide);
        return p;
    };
    const Planes all = filter(0, -1);
    // Rows 40–99 of 150: the passes run on fewer rows at each step; a band of one row too.
    for (const auto& [firstRow, endRow] : {std::pair{40, 100}, std::pair{0, 1}, {149, 150}}) {
        const Planes some = filter(firstRow, endRow);
        for (size_t e = 0; e < all.size(); ++e) {
            const std::vector<float>& input = e == 1 ? f.value : f.ratio;
            const size_t planes = all[e].size() / f.n;
            int differ = 0;
            for (size_t k = 0; k < planes; ++k)
                for (int y = 0; y < f.H; ++y)
                    for (int x = 0; x < f.W; ++x) {
                        const size_t i = k * f.n + size_t(y) * f.W + size_t(x);
                        const bool wanted = y >= firstRow && y < endRow;
                        ASSERT_EQ(floatBits(some[e][i]), floatBits(wanted ? all[e][i] : input[i]))
                            << "estimate " << e << " row " << y << " column " << x;
                        differ += wanted && all[e][i] != input[i];
                    }
            if (e != 1 && endRow - firstRow > 1) {
                EXPECT_GT(differ, 1000) << "estimate " << e;
            }
        }
    }
}

// The filter on 8 pixels at once (AVX2) gives the bits it gives on 4 (SSE2), for every kind
// of estimate: a pair with a lobe direction, a single value where a mask says, a pair filtered
// everywhere; and so does the width this CPU picks (atrousFilter).
TEST(Denoise, EightLanesGiveTheBitsOfFour) {
    if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "no AVX2 on this CPU";
    const FloorEstimates f;
    using Planes = std::vector<std::vector<float>>;
    auto filter = [&](int lanes) {
        Planes p{f.ratio, f.value, f.ratio};
        DenoiseEstimate a{&p[0], 2, &f.direction, &f.width},
            b{&p[1], 1, &f.direction, &f.width, &f.patch}, c{&p[2], 2};
        c.skipSettled = false;
        if (lanes == 0)
            atrousFilter({a, b, c}, f.guide);
        else
            atrousFilterLanes({a, b, c}, f.guide, 0, lanes);
        return p;
    };
    const Planes four = filter(4), eight = filter(8), chosen = filter(0);
    for (size_t e = 0; e < four.size(); ++e) {
        ASSERT_EQ(std::memcmp(four[e].data(), eight[e].data(), four[e].size() * sizeof(float)), 0)
            << "estimate " << e;
        ASSERT_EQ(std::memcmp(four[e].data(), chosen[e].data(), four[e].size() * sizeof(float)), 0)
            << "estimate " << e;
        EXPECT_NE(four[e], e == 1 ? f.value : f.ratio) << "estimate " << e << " not filtered";
    }
    const std::string isa = embreeIsaRequested();
    EXPECT_EQ(atrousLanes(), isa.empty() || isa == "avx2" || isa == "avx512" ? 8 : 4);
}

// A plane whose left half looks one way and right half another (as a glossy surface's
// pixels do where its mirror directions turn fast): a lobe-direction guide keeps the two
// halves' estimates apart for a narrow lobe, and lets them mix for a wide one; without it
// they mix across the whole 30-pixel reach.
TEST(Denoise, ADirectionGuideKeepsNarrowLobesApart) {
    constexpr int W = 64, H = 16;
    const size_t n = size_t(W) * H;
    DenoiseGuide guide;
    guide.width = W;
    guide.height = H;
    guide.position.resize(n);
    guide.normal.assign(n, glm::vec3(0.0f, 1.0f, 0.0f));
    guide.object.assign(n, 1.0f);
    guide.surface.assign(n, 1);
    std::vector<glm::vec3> direction(n);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const size_t p = size_t(y) * W + size_t(x);
            guide.position[p] = glm::vec3(0.01f * float(x), 0.0f, 0.01f * float(y));
            direction[p] = x < W / 2 ? glm::normalize(glm::vec3(0.3f, 1.0f, 0.0f))
                                     : glm::normalize(glm::vec3(-0.3f, 1.0f, 0.0f));
        }
    // A ratio of 0.2 on the left half and 0.9 on the right, each pixel a little noisy.
    auto sums = [&] {
        std::vector<float> v(2 * n);
        for (size_t p = 0; p < n; ++p) {
            const float ratio = (p % W) < W / 2 ? 0.2f : 0.9f;
            const float noise = 0.05f * (float(mixBits(p) >> 40) * 0x1p-24f - 0.5f);
            v[p] = ratio + noise;
            v[n + p] = 1.0f;
        }
        return v;
    };
    auto edgeError = [&](const std::vector<float>& v) {
        // The pixels next to the edge, against their own half's ratio.
        double e = 0.0;
        for (int y = 0; y < H; ++y)
            e += std::abs(v[size_t(y) * W + W / 2 - 1] - 0.2) +
                 std::abs(v[size_t(y) * W + W / 2] - 0.9);
        return e / (2 * H);
    };
    std::vector<float> narrow = sums(), wide = sums(), plain = sums();
    const std::vector<float> narrowWidth(n, 0.05f), wideWidth(n, 2.0f);
    atrousFilter({DenoiseEstimate{&narrow, 2, &direction, &narrowWidth}}, guide);
    atrousFilter({DenoiseEstimate{&wide, 2, &direction, &wideWidth}}, guide);
    atrousFilter(plain, 2, guide);
    std::printf("edge error: narrow lobe %.4f, wide lobe %.4f, no direction guide %.4f\n",
                edgeError(narrow), edgeError(wide), edgeError(plain));
    EXPECT_LT(edgeError(narrow), 0.03);
    EXPECT_GT(edgeError(wide), 0.1);
    EXPECT_NEAR(edgeError(wide), edgeError(plain), 0.02);
}

// The denoiser against the per-pixel estimate, both at 16 rays, on a box on a floor under a
// sky (environment shadows and ray-traced AO), against a 1024-ray per-pixel reference: the
// RMS error falls to under a third, the mean stays within 2 %, pixels that no ray finds
// blocked keep the unshadowed value exactly, and the thread count does not matter.
TEST(Denoise, CleanerThanThePerPixelEstimateAndUnbiasedInTheMean) {
    Scene scene = emptyScene();
    addFloor(scene, 3.0f);
    addBox(scene, {-0.3f, 0.0f, -0.3f}, {0.3f, 0.7f, 0.3f});
    const RayCaster caster(scene);
    Light light;
    light.type = LightType::Environment;
    light.ibl = skyWithSun(glm::normalize(glm::vec3(0.5f, 1.0f, 0.2f)), 1.0f);
    const Camera camera = Camera::lookAt({1.5, 2.2, 2.6}, {0.0, 0.2, 0.0}, {0, 1, 0}, 0.8);
    const ImageBuf gbuf = gbufferOf(scene, camera, 160, 120);
    LightingParams p;
    p.environmentSamples = 16;
    p.aoSamples = 16;
    p.aoDistance = 0.5f;
    p.writeAO = true;
    const ImageBuf denoised = shade(gbuf, {light}, &caster, p, 2);
    const ImageBuf oneThread = shade(gbuf, {light}, &caster, p, 1);
    p.denoise = false;
    const ImageBuf raw = shade(gbuf, {light}, &caster, p, 2);
    p.environmentSamples = p.aoSamples = 1024;
    const ImageBuf reference = shade(gbuf, {light}, &caster, p, 2);
    double rawError = 0.0, denoisedError = 0.0, sum = 0.0, sumReference = 0.0;
    int covered = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) {
            ASSERT_EQ(px(denoised, x, y)[1], px(oneThread, x, y)[1]) << x << "," << y;
            if (!(px(gbuf, x, y)[gbuf.spec().channelindex("A")] > 0.0f)) continue;
            ++covered;
            const double r = px(reference, x, y)[1];
            rawError += std::pow(px(raw, x, y)[1] - r, 2.0);
            denoisedError += std::pow(px(denoised, x, y)[1] - r, 2.0);
            sum += px(denoised, x, y)[1];
            sumReference += r;
        }
    ASSERT_GT(covered, 10000);
    rawError = std::sqrt(rawError / covered);
    denoisedError = std::sqrt(denoisedError / covered);
    std::printf("RMS error at 16 rays: per pixel %.5f, denoised %.5f; mean %.5f vs %.5f\n",
                rawError, denoisedError, sum / covered, sumReference / covered);
    EXPECT_LT(denoisedError, rawError / 3.0);
    EXPECT_NEAR(sum / sumReference, 1.0, 0.02);
    // With nothing to block a ray, every filtered ratio is exactly 1: the unshadowed value.
    Scene floorOnly = emptyScene();
    addFloor(floorOnly, 3.0f);
    const RayCaster floorCaster(floorOnly);
    const ImageBuf floorG = gbufferOf(floorOnly, camera, 80, 60);
    p.environmentSamples = p.aoSamples = 16;
    p.shadows = true;
    p.denoise = true;
    const ImageBuf floorLit = shade(floorG, {light}, &floorCaster, p, 2);
    p.shadows = false;
    p.aoSamples = 0;
    const ImageBuf floorOpen = shade(floorG, {light}, &floorCaster, p, 2);
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x) {
            ASSERT_EQ(px(floorLit, x, y)[1], px(floorOpen, x, y)[1]) << x << "," << y;
            ASSERT_EQ(px(floorLit, x, y)[4], 1.0f);
        }
}

// A coarse sphere alone under a uniform sky: a convex mesh cannot hide any of the sky from
// itself, so with smooth normals (which lean past the triangles' planes at the silhouette and
// along the terminator) every pixel's environment visibility and AO are exactly 1. Rays
// below a triangle's own plane used to hit the sphere and blacken pixels at its rim.
TEST(EnvironmentShadows, AConvexMeshWithSmoothNormalsDoesNotShadowItself) {
    Scene scene = emptyScene();
    addSphere(scene, {0.0f, 0.0f, 0.0f}, 0.5f, 10);
    const RayCaster caster(scene);
    const Light light = uniformSky();
    const Camera camera = Camera::lookAt({0.0, 0.3, 2.0}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.7);
    const ImageBuf gbuf = gbufferOf(scene, camera, 96, 96);
    LightingParams p;
    p.environmentSamples = 32;
    p.aoSamples = 32;
    p.aoDistance = INFINITY;
    p.writeAO = true;
    p.denoise = false;
    const ImageBuf lit = shade(gbuf, {light}, &caster, p);
    p.shadows = false;
    p.aoSamples = 0;
    const ImageBuf open = shade(gbuf, {light}, &caster, p);
    int covered = 0;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x) {
            if (!(px(gbuf, x, y)[gbuf.spec().channelindex("A")] > 0.0f)) continue;
            ++covered;
            ASSERT_EQ(px(lit, x, y)[4], 1.0f) << x << "," << y;
            ASSERT_EQ(px(lit, x, y)[1], px(open, x, y)[1]) << x << "," << y;
        }
    EXPECT_GT(covered, 1500);
}
