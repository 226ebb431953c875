// Tiled light culling against the brute-force reference: it may skip only what is exactly zero.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/lights/light_culling.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/scene.h>
#include <gtest/gtest.h>
#include <random>

using namespace dhdr;
using OIIO::ImageBuf;

namespace {

const float* px(const ImageBuf& img, int x, int y) {
    return static_cast<const float*>(img.pixeladdr(x, y));
}

// Largest |culled − brute| / max(|brute|, 1e-6) over all pixels and channels.
double maxRelativeDifference(const ImageBuf& gbuf, const std::vector<Light>& lights,
                             LightingStats& culledStats, LightingStats& bruteStats) {
    ImageBuf culled, brute;
    LightingParams p;
    EXPECT_TRUE(shadeGBuffer(culled, gbuf, {lights}, p, {}, 0, &culledStats));
    p.bruteForce = true;
    EXPECT_TRUE(shadeGBuffer(brute, gbuf, {lights}, p, {}, 0, &bruteStats));
    double worst = 0.0;
    for (int y = 0; y < gbuf.spec().height; ++y)
        for (int x = 0; x < gbuf.spec().width; ++x)
            for (int c = 0; c < 4; ++c) {
                const double a = px(culled, x, y)[c], b = px(brute, x, y)[c];
                worst = std::max(worst, std::abs(a - b) / std::max(std::abs(b), 1e-6));
            }
    return worst;
}

struct Rng {
    std::mt19937 engine;
    explicit Rng(unsigned seed) : engine(seed) {}
    double operator()(double lo, double hi) { return lo + (hi - lo) * (engine() / 4294967296.0); }
};

// N random lights of every local type inside [lo, hi], plus an ambient and a directional.
std::vector<Light> randomLights(int n, glm::vec3 lo, glm::vec3 hi, double rmin, double rmax,
                                unsigned seed) {
    Rng u(seed);
    std::vector<Light> lights;
    for (int i = 0; i < n; ++i) {
        Light l;
        l.type = std::array<LightType, 4>{LightType::Point, LightType::Spot, LightType::Sphere,
                                          LightType::Rectangle}[size_t(i % 4)];
        l.position = glm::vec3(u(lo.x, hi.x), u(lo.y, hi.y), u(lo.z, hi.z));
        l.color = glm::vec3(u(0.2, 1.0), u(0.2, 1.0), u(0.2, 1.0));
        l.intensity = float(u(0.001, 0.02));
        l.range = float(u(rmin, rmax));
        l.direction = glm::normalize(glm::vec3(u(-1, 1), u(-1, 0.2), u(-1, 1)));
        l.up = glm::normalize(glm::cross(l.direction, glm::vec3(0.3f, 0.5f, 0.8f)));
        l.innerConeAngle = float(u(0.0, 0.4));
        l.outerConeAngle = l.innerConeAngle + float(u(0.05, 0.8));
        l.radius = l.range * 0.1f;
        l.width = l.range * 0.2f;
        l.height = l.range * 0.1f;
        lights.push_back(l);
    }
    Light ambient;
    ambient.type = LightType::Ambient;
    ambient.intensity = 0.001f;
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.2f, -1.0f, 0.4f));
    sun.intensity = 0.01f;
    lights.insert(lights.begin() + n / 2, ambient);
    lights.push_back(sun);
    return lights;
}

Mesh box(glm::vec3 lo, glm::vec3 hi, int object) {
    Mesh m;
    m.object = object;
    const glm::vec3 n[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (int f = 0; f < 6; ++f) {
        const int axis = f / 2;
        const float side = f % 2 ? hi[axis] : lo[axis];
        const int a = (axis + 1) % 3, b = (axis + 2) % 3;
        const glm::vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        const unsigned base = unsigned(m.positions.size());
        for (const glm::vec2& c : corners) {
            glm::vec3 p;
            p[axis] = side;
            p[a] = c.x ? hi[a] : lo[a];
            p[b] = c.y ? hi[b] : lo[b];
            m.positions.push_back(p);
            m.normals.push_back(n[f]);
        }
        m.triangles.push_back({base, base + 1, base + 2});
        m.triangles.push_back({base, base + 2, base + 3});
    }
    return m;
}

// Thin poles 2-3 m from the camera in front of a wall 20 m away: most tiles on the poles'
// edges hold two depths far apart.
Scene polesBeforeAWall() {
    Scene scene;
    scene.materials.resize(1);
    scene.materials[0].metallic = 0.0f;
    scene.materials[0].roughness = 0.6f;
    scene.materials[0].baseColor = glm::vec3(0.7f);
    scene.objectNames = {"wall"};
    scene.meshes.push_back(box({-30, -20, -21}, {30, 20, -20}, 0));
    Rng u(5);
    for (int i = 0; i < 24; ++i) {
        const float x = float(u(-1.2, 1.2)), z = float(u(-3.0, -2.0));
        scene.objectNames.push_back("pole");
        scene.meshes.push_back(box({x, -2, z}, {x + 0.02f, 2, z + 0.02f}, i + 1));
    }
    return scene;
}

} // namespace

TEST(LightCulling, EqualsBruteForceOnCornellBoxWith1000Lights) {
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(std::string(DHDR_TESTDATA) + "/cornell_box.gltf", scene, error));
    GBufferParams params;
    params.width = 256;
    params.height = 256;
    ImageBuf gbuf;
    ASSERT_TRUE(renderGBuffer(gbuf, scene, scene.cameras[0].camera, params));
    const auto lights = randomLights(1000, {0, 0, 0}, {0.556f, 0.549f, 0.559f}, 0.02, 0.12, 11);
    LightingStats culled, brute;
    EXPECT_LE(maxRelativeDifference(gbuf, lights, culled, brute), 1e-5);
    EXPECT_LT(culled.lightEvaluations * 10, brute.lightEvaluations);
}

// A frame shaded strip by strip (as dhdr-light streams it), with strips of whole tile rows
// and with strips that cut tiles, gives the whole frame's pixels bit for bit, culled and
// brute force, including the directional and ambient lights that every tile holds.
TEST(LightCulling, StripsGiveTheWholeFramesPixels) {
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(std::string(DHDR_TESTDATA) + "/cornell_box.gltf", scene, error));
    GBufferParams params;
    params.width = 200;
    params.height = 150;
    ImageBuf gbuf;
    ASSERT_TRUE(renderGBuffer(gbuf, scene, scene.cameras[0].camera, params));
    const auto lights = randomLights(400, {0, 0, 0}, {0.556f, 0.549f, 0.559f}, 0.02, 0.12, 17);
    for (const bool bruteForce : {false, true}) {
        LightingParams p;
        p.bruteForce = bruteForce;
        ImageBuf whole;
        ASSERT_TRUE(shadeGBuffer(whole, gbuf, {lights}, p));
        for (const int rows : {16, 64, 37}) {
            LightingParams strips = p;
            strips.frame = gbuf.roi();
            ImageBuf strip, lit;
            for (int y = 0; y < 150; y += rows) {
                const OIIO::ROI band(0, 200, y, std::min(150, y + rows), 0, 1, 0, gbuf.nchannels());
                strip = OIIO::ImageBufAlgo::cut(gbuf, band);
                strip.set_origin(0, band.ybegin);
                ASSERT_TRUE(shadeGBuffer(lit, strip, {lights}, strips)) << lit.geterror();
                for (int yy = band.ybegin; yy < band.yend; ++yy)
                    for (int x = 0; x < 200; ++x)
                        for (int c = 0; c < 4; ++c)
                            ASSERT_EQ(px(lit, x, yy)[c], px(whole, x, yy)[c])
                                << "rows " << rows << " at " << x << "," << yy
                                << (bruteForce ? " brute force" : " culled");
            }
        }
    }
}

TEST(LightCulling, EqualsBruteForceAcrossStrongDepthDiscontinuities) {
    const Scene scene = polesBeforeAWall();
    const Camera camera = Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 0.8);
    GBufferParams params;
    params.width = 240;
    params.height = 160;
    ImageBuf gbuf;
    ASSERT_TRUE(renderGBuffer(gbuf, scene, camera, params));
    // Small lights among the poles and on the wall.
    auto lights = randomLights(300, {-1.5f, -1.0f, -3.2f}, {1.5f, 1.0f, -1.8f}, 0.05, 0.3, 3);
    const auto far = randomLights(300, {-8, -5, -19.8f}, {8, 5, -19.0f}, 0.5, 2.0, 4);
    lights.insert(lights.end(), far.begin(), far.end());
    LightingStats culled, brute;
    EXPECT_LE(maxRelativeDifference(gbuf, lights, culled, brute), 1e-5);
    // The depth slices keep the near lights off the wall behind a pole's edge: far fewer
    // evaluations than the lights' tile lists hold per pixel.
    EXPECT_LT(culled.lightEvaluations * 20, brute.lightEvaluations);
}

namespace {

// The G-buffer of a floor y = 0 seen from 3 m above.
ImageBuf floorGBuffer() {
    Scene scene;
    scene.materials.resize(1);
    scene.materials[0].metallic = 0.0f;
    scene.objectNames = {"floor"};
    scene.meshes.push_back(box({-5, -1, -5}, {5, 0, 5}, 0));
    static Camera camera;
    // Straight down, so that the floor's planar depth is 3 at every pixel.
    camera = Camera::lookAt({0, 3, 0}, {0, 0, 0}, {0, 0, -1}, 1.2);
    GBufferParams params;
    params.width = 128;
    params.height = 128;
    ImageBuf gbuf;
    renderGBuffer(gbuf, scene, camera, params);
    return gbuf;
}

TileLightLists cull(const ImageBuf& gbuf, const std::vector<Light>& lights) {
    gbuffer::CameraInfo camera;
    std::string error;
    EXPECT_TRUE(gbuffer::readCamera(gbuf.spec(), camera, error)) << error;
    const size_t nch = size_t(gbuf.nchannels());
    const DepthView depth{static_cast<const float*>(gbuf.localpixels()) +
                              gbuf.spec().channelindex("Z"),
                          nch, nch * size_t(gbuf.spec().width)};
    TileLightLists tiles;
    tiles.build(lights, camera, depth, gbuf.spec().width, gbuf.spec().height, 16);
    return tiles;
}

} // namespace

TEST(LightCulling, LightEndingJustAboveTheSurfaceIsInNoTile) {
    const ImageBuf gbuf = floorGBuffer();
    Light light;
    light.position = glm::vec3(0.0f, 1.0f, 0.0f);
    light.intensity = 10.0f;
    light.range = 0.999f; // the floor is 1 m below
    EXPECT_EQ(cull(gbuf, {light}).totalEntries(), 0u);
    ImageBuf hdr;
    LightingParams p;
    p.bruteForce = true;
    ASSERT_TRUE(shadeGBuffer(hdr, gbuf, {{light}}, p));
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x)
            ASSERT_EQ(px(hdr, x, y)[1], 0.0f);
    // A millimetre more and it reaches the floor right below it, in the tiles there only.
    light.range = 1.001f;
    const TileLightLists tiles = cull(gbuf, {light});
    EXPECT_GT(tiles.totalEntries(), 0u);
    EXPECT_LE(tiles.totalEntries(), 4u);
    EXPECT_EQ(tiles.at(64, 64).size(), 1u);
    EXPECT_TRUE(tiles.at(0, 0).empty());
}

TEST(LightCulling, SpotConeBoundsTheTiles) {
    const ImageBuf gbuf = floorGBuffer();
    Light spot;
    spot.type = LightType::Spot;
    spot.position = glm::vec3(0.0f, 1.0f, 0.0f);
    spot.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    spot.range = 2.0f;
    spot.innerConeAngle = 0.2f;
    spot.outerConeAngle = 0.3f; // a disk of radius tan(0.3) ≈ 0.31 m on the floor
    Light point = spot;
    point.type = LightType::Point;
    const size_t spotEntries = cull(gbuf, {spot}).totalEntries();
    // The range sphere alone covers a disk of radius √3 ≈ 1.73 m: ~30 times the area.
    EXPECT_LT(spotEntries * 8, cull(gbuf, {point}).totalEntries());
    LightingStats culled, brute;
    EXPECT_LE(maxRelativeDifference(gbuf, {spot}, culled, brute), 1e-6);
    // Lit inside the cone, exactly dark outside it.
    ImageBuf hdr;
    ASSERT_TRUE(shadeGBuffer(hdr, gbuf, {{spot}}));
    const int idx = hdr.spec().channelindex("R");
    int lit = 0;
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x) {
            const float* g = px(gbuf, x, y);
            const glm::vec3 P(g[gbuf.spec().channelindex("P.X")], 0.0f,
                              g[gbuf.spec().channelindex("P.Z")]);
            const float angle = std::atan(std::hypot(P.x, P.z) / 1.0f);
            if (angle > 0.301f) {
                ASSERT_EQ(px(hdr, x, y)[idx], 0.0f) << x << "," << y;
            }
            if (angle < 0.299f) {
                ASSERT_GT(px(hdr, x, y)[idx], 0.0f);
                ++lit;
            }
        }
    EXPECT_GT(lit, 100);
}
