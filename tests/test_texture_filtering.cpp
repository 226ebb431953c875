// Textures filtered by the pixel's footprint (issue 45): mip levels against box averages and
// the image's mean, the ray-differential footprint against its closed form on a plane facing
// the camera, and a receding checkered floor's G-buffer against the average of 16 × 16 rays
// per pixel.
#include "scene_builder.h"

#include <cmath>
#include <dhdr/deferred/geometry/uv_footprint.h>
#include <dhdr/deferred/scene/texture.h>
#include <gtest/gtest.h>

using namespace dhdr;
using namespace dhdr::test;

namespace {

double srgbDecode(double v) {
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

// An 8-bit sRGB texture of random codes (a fixed sequence), as the loader keeps a PNG.
Texture randomCodes(int width, int height, unsigned seed) {
    static const auto table = [] {
        auto t = std::make_shared<std::vector<float>>(256);
        for (int i = 0; i < 256; ++i)
            (*t)[size_t(i)] = float(srgbDecode(i / 255.0));
        return t;
    }();
    static const auto linear = [] {
        auto t = std::make_shared<std::vector<float>>(256);
        for (int i = 0; i < 256; ++i)
            (*t)[size_t(i)] = float(i / 255.0);
        return t;
    }();
    Texture t;
    t.width = width;
    t.height = height;
    t.colorTable = table;
    t.alphaTable = linear;
    unsigned s = seed;
    for (int i = 0; i < 4 * width * height; ++i) {
        s = s * 1664525u + 1013904223u;
        t.codes8.push_back(std::uint8_t(s >> 24));
    }
    return t;
}

glm::dvec4 levelMean(const Texture& t, const TextureLevel& level) {
    glm::dvec4 sum(0.0);
    const size_t n = size_t(level.width) * size_t(level.height);
    for (size_t i = 0; i < n; ++i)
        sum += glm::dvec4(t.texel(level, i));
    return sum / double(n);
}

// A checker of `cell`-texel squares, black and white, `size` texels square, in float.
Texture checker(int size, int cell) {
    Texture t;
    t.name = "checker";
    t.width = t.height = size;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float v = (x / cell + y / cell) % 2 == 0 ? 1.0f : 0.0f;
            t.rgba.insert(t.rgba.end(), {v, v, v, 1.0f});
        }
    buildMipmaps(t);
    return t;
}

} // namespace

TEST(TextureFiltering, MipLevelsAreBoxAveragesKeepingTheMean) {
    // Even sizes: each texel of level 1 is the mean of its 2 × 2 texels of level 0, rounded to
    // the nearest code. Odd sizes: every level's mean is the image's (its texels' weights sum
    // to 1), within the rounding to codes (at most half the widest step between codes).
    const Texture even = [] {
        Texture t = randomCodes(16, 8, 7);
        buildMipmaps(t);
        return t;
    }();
    ASSERT_EQ(even.levels(), 5); // 16×8, 8×4, 4×2, 2×1, 1×1
    EXPECT_EQ(even.level(4).width, 1);
    EXPECT_EQ(even.level(4).height, 1);
    const double halfStep = 0.5 * (1.0 - srgbDecode(254.0 / 255.0));
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) {
            glm::dvec4 box(0.0);
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i)
                    box += glm::dvec4(even.texel(size_t(2 * y + j) * 16 + size_t(2 * x + i)));
            box /= 4.0;
            const glm::vec4 mip = even.texel(even.level(1), size_t(y) * 8 + size_t(x));
            for (int c = 0; c < 4; ++c)
                EXPECT_NEAR(mip[c], box[c], halfStep) << x << "," << y << " channel " << c;
        }
    for (const glm::ivec2 size : {glm::ivec2(37, 21), glm::ivec2(5, 3), glm::ivec2(1, 9)}) {
        Texture t = randomCodes(size.x, size.y, 11);
        buildMipmaps(t);
        const glm::dvec4 mean = levelMean(t, t);
        for (int k = 1; k < t.levels(); ++k) {
            EXPECT_EQ(t.level(k).width, std::max(1, t.level(k - 1).width / 2));
            EXPECT_EQ(t.level(k).height, std::max(1, t.level(k - 1).height / 2));
            const glm::dvec4 m = levelMean(t, t.level(k));
            // Each level's rounding adds at most half a step to its mean.
            for (int c = 0; c < 4; ++c)
                EXPECT_NEAR(m[c], mean[c], k * halfStep)
                    << size.x << "x" << size.y << " level " << k << " channel " << c;
        }
        EXPECT_EQ(t.level(t.levels() - 1).width * t.level(t.levels() - 1).height, 1);
    }
}

TEST(TextureFiltering, MagnifiedLookupsAreTheBilinearOnes) {
    // A footprint under a texel: the filtered lookup is the unfiltered one, bit for bit, so
    // that textures seen close up keep today's pixels.
    Texture t = randomCodes(32, 32, 3);
    buildMipmaps(t);
    for (const TextureFilter filter : {TextureFilter::Trilinear, TextureFilter::Anisotropic})
        for (int i = 0; i < 50; ++i) {
            const glm::vec2 uv(0.013f * float(i), 0.7f - 0.029f * float(i));
            const glm::vec2 dx(0.9f / 32.0f, 0.0f), dy(0.1f / 32.0f, 0.8f / 32.0f);
            const glm::vec4 a = t.sample(uv, dx, dy, {}, filter), b = t.sample(uv);
            EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << i;
        }
    // Minified by 4 along both axes: level 2 exactly (lod 2, no blend with level 3).
    const glm::vec2 uv(0.3f, 0.6f);
    const glm::vec4 a = t.sample(uv, glm::vec2(4.0f / 32.0f, 0.0f), glm::vec2(0.0f, 4.0f / 32.0f),
                                 {}, TextureFilter::Trilinear);
    Texture level2;
    static_cast<TextureLevel&>(level2) = t.level(2);
    level2.colorTable = t.colorTable;
    level2.alphaTable = t.alphaTable;
    const glm::vec4 b = level2.sample(uv);
    for (int c = 0; c < 4; ++c)
        EXPECT_FLOAT_EQ(a[c], b[c]);
}

TEST(TextureFiltering, FootprintOnAPlaneFacingTheCameraIsItsClosedForm) {
    // A 4 × 4 quad at distance 10 facing a camera of vertical field of view 40° over 200 rows:
    // a pixel spans 2·10·tan 20° / 200 on it, everywhere (the plane is parallel to the image),
    // so du/dx = that / 4 with u along +x, and v grows down the image as the rows do. The
    // second UV set is the first × 3.
    Scene scene;
    scene.materials.push_back(Material{});
    addQuad(scene, {-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0});
    Mesh& quad = scene.meshes[0];
    quad.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    for (const glm::vec2& uv : quad.uvs)
        quad.uvs1.push_back(3.0f * uv);
    const double yfov = glm::radians(40.0);
    const Camera camera = Camera::lookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, yfov);
    const RayCaster caster(scene);
    const double pixel = 2.0 * std::tan(yfov / 2.0) / 200.0; // radians between neighbours
    const double expected = 10.0 * pixel / 4.0;
    // Double rays and planes, the result rounded to float.
    const double tolerance = 1e-6 * expected;
    for (const glm::ivec2 p : {glm::ivec2(150, 100), glm::ivec2(120, 70), glm::ivec2(181, 133)}) {
        const Ray ray = camera.primaryRay(p.x, p.y, 300, 200);
        const RayHit hit = caster.intersect(ray);
        ASSERT_TRUE(hit.hit);
        const UvFootprint f =
            uvFootprint(scene, hit, ray, camera.primaryRay(p.x + 1, p.y, 300, 200),
                        camera.primaryRay(p.x, p.y + 1, 300, 200), TextureFilter::Trilinear);
        EXPECT_NEAR(f.dx[0].x, expected, tolerance);
        EXPECT_NEAR(f.dy[0].y, expected, tolerance);
        EXPECT_NEAR(f.dx[0].y, 0.0, tolerance);
        EXPECT_NEAR(f.dy[0].x, 0.0, tolerance);
        EXPECT_NEAR(f.dx[1].x, 3.0 * expected, 3.0 * tolerance);
        EXPECT_NEAR(f.dy[1].y, 3.0 * expected, 3.0 * tolerance);
    }
    // Seen edge-on (the neighbour's ray parallel to the plane): the widest footprint.
    Ray along;
    along.origin = {-5, 0, 0};
    along.direction = {1, 0, 0};
    RayHit edge;
    edge.hit = true;
    edge.mesh = 0;
    edge.triangle = 0;
    edge.u = edge.v = 0.25f;
    const UvFootprint f = uvFootprint(scene, edge, along, along, along, TextureFilter::Trilinear);
    EXPECT_GE(f.dx[0].x, 1e7f);
    EXPECT_GE(f.dy[0].y, 1e7f);
}

namespace {

// A 40 × 40 floor at y = 0 tiled 20 times over by a 64-texel checker of 2-texel cells, seen
// from 1 unit above looking towards the horizon: its texels go from magnified near the
// camera to hundreds a pixel far off.
Scene checkeredFloor() {
    Scene scene;
    scene.textures.push_back(checker(64, 2));
    Material m;
    m.name = "floor";
    m.baseColorTexture.texture = 0;
    scene.materials.push_back(m);
    scene.objectNames.push_back("floor");
    addQuad(scene, {-20, 0, 20}, {20, 0, 20}, {20, 0, -20}, {-20, 0, -20});
    Mesh& floor = scene.meshes[0];
    floor.uvs = {{0, 20}, {20, 20}, {20, 0}, {0, 0}};
    return scene;
}

// The albedo's red of every pixel of a G-buffer of `scene` at `width` × `height`.
std::vector<float> albedo(const Scene& scene, const Camera& camera, int width, int height,
                          TextureFilter filter) {
    GBufferParams params;
    params.width = width;
    params.height = height;
    params.textureFilter = filter;
    ImageBuf g;
    EXPECT_TRUE(renderGBuffer(g, scene, camera, params, 2)) << g.geterror();
    const int c = g.spec().channelindex("albedo.R"), a = g.spec().channelindex("A");
    std::vector<float> out;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            out.push_back(px(g, x, y)[a] > 0.0f ? px(g, x, y)[c] : -1.0f);
    return out;
}

} // namespace

TEST(TextureFiltering, ARecedingCheckerApproachesThePixelAverage) {
    // Against each pixel's albedo averaged over a 16 × 16 grid of rays (the pixel's box, the
    // reference), over the pixels whose 256 rays all meet the floor: one bilinear lookup
    // aliases (its error is the checker's contrast at a distance); trilinear takes the error
    // below a third of that, anisotropic below trilinear's, and both keep the floor's mean.
    const Scene scene = checkeredFloor();
    const Camera camera = Camera::lookAt({0, 1, 19}, {0, 0.6, 0}, {0, 1, 0}, glm::radians(40.0));
    constexpr int kW = 96, kH = 64, kS = 16;
    const std::vector<float> fine =
        albedo(scene, camera, kW * kS, kH * kS, TextureFilter::Bilinear);
    std::vector<double> reference(size_t(kW * kH), -1.0);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            double sum = 0.0;
            bool all = true;
            for (int j = 0; j < kS && all; ++j)
                for (int i = 0; i < kS; ++i) {
                    const float v = fine[size_t((y * kS + j) * kW * kS + x * kS + i)];
                    all = all && v >= 0.0f;
                    sum += v;
                }
            if (all) reference[size_t(y * kW + x)] = sum / (kS * kS);
        }
    auto error = [&](TextureFilter filter, double& mean) {
        const std::vector<float> one = albedo(scene, camera, kW, kH, filter);
        double squares = 0.0, sum = 0.0, referenceSum = 0.0;
        int n = 0;
        for (size_t p = 0; p < one.size(); ++p)
            if (reference[p] >= 0.0) {
                squares += (one[p] - reference[p]) * (one[p] - reference[p]);
                sum += one[p];
                referenceSum += reference[p];
                ++n;
            }
        EXPECT_GT(n, kW * kH / 3);
        mean = (sum - referenceSum) / n;
        return std::sqrt(squares / n);
    };
    double biasBilinear, biasTrilinear, biasAnisotropic;
    const double bilinear = error(TextureFilter::Bilinear, biasBilinear);
    const double trilinear = error(TextureFilter::Trilinear, biasTrilinear);
    const double anisotropic = error(TextureFilter::Anisotropic, biasAnisotropic);
    std::printf("RMS error against 16x16 rays: bilinear %.4f, trilinear %.4f, anisotropic %.4f; "
                "mean offset %.4f, %.4f, %.4f\n",
                bilinear, trilinear, anisotropic, biasBilinear, biasTrilinear, biasAnisotropic);
    EXPECT_GT(bilinear, 0.1); // the test sees aliasing to remove
    EXPECT_LT(trilinear, bilinear / 3.0);
    EXPECT_LT(anisotropic, trilinear);
    EXPECT_LT(std::abs(biasTrilinear), 0.01);
    EXPECT_LT(std::abs(biasAnisotropic), 0.01);
}

TEST(TextureFiltering, ANormalMapsSpreadWidensTheRoughness) {
    // A normal map of columns tilted ±30° about v in turn: seen close up each pixel has its own
    // normal and the material's roughness, bit for bit; seen from afar a pixel covers 8 texels,
    // its filtered vector is cos 30° long, and the GGX lobe widens by the spread of a von
    // Mises-Fisher lobe of that mean length: α'² = α² + 2/κ, κ = (3r − r³)/(1 − r²), r = cos 30°.
    const double tilt = glm::radians(30.0);
    Texture map;
    map.name = "ridges";
    map.width = map.height = 64;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const float sx = float((x % 2 ? 1.0 : -1.0) * std::sin(tilt));
            map.rgba.insert(map.rgba.end(),
                            {0.5f + 0.5f * sx, 0.5f, 0.5f + 0.5f * float(std::cos(tilt)), 1.0f});
        }
    buildMipmaps(map);
    map.normalLength = meanNormalLength(map);
    EXPECT_NEAR(map.normalLength, 1.0, 1e-6);
    Scene scene;
    scene.textures.push_back(map);
    Material m;
    m.name = "ridged";
    m.roughness = 0.3f;
    m.normalTexture.texture = 0;
    scene.materials.push_back(m);
    scene.objectNames.push_back("quad");
    addQuad(scene, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    Mesh& quad = scene.meshes[0];
    quad.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    quad.tangents.assign(4, glm::vec3(1, 0, 0));
    quad.bitangents.assign(4, glm::vec3(0, -1, 0));
    auto roughnessAt = [&](double distance, int size, TextureFilter filter) {
        // The quad fills size / ratio pixels: 2 units at `distance` under a 40° field.
        GBufferParams params;
        params.width = params.height = size;
        params.textureFilter = filter;
        ImageBuf g;
        const Camera camera =
            Camera::lookAt({0, 0, distance}, {0, 0, 0}, {0, 1, 0}, glm::radians(40.0));
        EXPECT_TRUE(renderGBuffer(g, scene, camera, params, 2)) << g.geterror();
        return px(g, size / 2, size / 2)[g.spec().channelindex("roughness")];
    };
    // Close up: 64 texels over ~180 pixels, magnified.
    for (const TextureFilter f : {TextureFilter::Trilinear, TextureFilter::Anisotropic})
        EXPECT_EQ(roughnessAt(3.0, 256, f), 0.3f);
    // Far: 2 units over 8 pixels, 8 texels a pixel.
    const double r = std::cos(tilt);
    const double kappa = (3.0 * r - r * r * r) / (1.0 - r * r);
    const double alpha = 0.3 * 0.3;
    const double expected = std::pow(alpha * alpha + 2.0 / kappa, 0.25);
    const double distance = 2.0 / (8.0 / 64.0 * 2.0 * std::tan(glm::radians(20.0)));
    for (const TextureFilter f : {TextureFilter::Trilinear, TextureFilter::Anisotropic})
        EXPECT_NEAR(roughnessAt(distance, 64, f), expected, 1e-4);
    EXPECT_EQ(roughnessAt(distance, 64, TextureFilter::Bilinear), 0.3f);
}
