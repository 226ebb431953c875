// Transparent surfaces and deep G-buffers against closed forms: a Blend pane over a wall
// composites as 0.4 · pane + 0.6 · wall (each lit as a flat G-buffer of it alone would be), its
// shadow is exactly 0.6 of the light, a Mask card shows and casts holes, culled equals brute
// force per sample, results do not depend on the thread count, and deep files are read back
// with OpenEXR's own deep reader and in any sample order.
#include <ImfChannelList.h>
#include <ImfDeepFrameBuffer.h>
#include <ImfDeepScanLineInputFile.h>
#include <ImfDeepScanLineOutputFile.h>
#include <ImfHeader.h>
#include <ImfPartType.h>
#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cmath>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/io/deep_exr.h>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

using namespace dhdr;
using OIIO::ImageBuf;

namespace {

const float* px(const ImageBuf& img, int x, int y) {
    return static_cast<const float*>(img.pixeladdr(x, y));
}

// A quad a b c d (counter-clockwise seen from where its normal points), with UVs over [0, 1]².
void addQuad(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, int material,
             int object) {
    Mesh m;
    m.positions = {a, b, c, d};
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    m.normals = {n, n, n, n};
    m.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.material = material;
    m.object = object;
    scene.meshes.push_back(m);
}

Material lambert(const char* name, glm::vec3 albedo) {
    Material m;
    m.name = name;
    m.baseColor = albedo;
    m.roughness = 1.0f;
    m.metallic = 0.0f;
    return m;
}

// The wall z = 0 over [−1, 1]² facing +Z (material 0), optionally a pane at z = 0.5 over
// [−0.5, 0.5]² (material 1: Blend, alpha 0.4, bluish).
Scene paneScene(bool wall, bool pane) {
    Scene scene;
    scene.materials.push_back(lambert("wall", glm::vec3(0.8f, 0.7f, 0.6f)));
    Material glass = lambert("glass", glm::vec3(0.3f, 0.5f, 0.9f));
    glass.alpha = 0.4f;
    glass.alphaMode = AlphaMode::Blend;
    glass.roughness = 0.3f;
    scene.materials.push_back(glass);
    scene.objectNames = {"wall", "pane"};
    if (wall) addQuad(scene, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, 0, 0);
    if (pane)
        addQuad(scene, {-0.5f, -0.5f, 0.5f}, {0.5f, -0.5f, 0.5f}, {0.5f, 0.5f, 0.5f},
                {-0.5f, 0.5f, 0.5f}, 1, 1);
    return scene;
}

const Camera kFront = Camera::lookAt({0.1, 0.05, 3.0}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.7);

Light pointLight(glm::vec3 p, float intensity) {
    Light l;
    l.type = LightType::Point;
    l.position = p;
    l.intensity = intensity;
    l.range = INFINITY;
    return l;
}

DeepGBuffer deepOf(const Scene& scene, const Camera& camera, int w, int h, int nthreads = 0) {
    GBufferParams p;
    p.width = w;
    p.height = h;
    const GBufferRenderer renderer(scene, camera, p);
    DeepGBuffer g;
    EXPECT_TRUE(renderer.renderDeep(g, {}, nthreads));
    return g;
}

ImageBuf flatOf(const Scene& scene, const Camera& camera, int w, int h) {
    ImageBuf g;
    GBufferParams p;
    p.width = w;
    p.height = h;
    EXPECT_TRUE(renderGBuffer(g, scene, camera, p)) << g.geterror();
    return g;
}

// A deep G-buffer written as dhdr-gbuffer writes it (the contract's file types, deep scanlines).
bool writeDeep(const std::string& path, const DeepGBuffer& deep) {
    auto out = OIIO::ImageOutput::create(path);
    OIIO::ImageSpec spec = deep.spec;
    spec.deep = true;
    spec.channelformats = gbuffer::channelFormats(deep.spec.channelnames);
    OIIO::DeepData data;
    toDeepData(deep, deep.spec.y, deep.spec.y + deep.spec.height, data);
    return out && out->open(path, spec) &&
           out->write_deep_scanlines(deep.spec.y, deep.spec.y + deep.spec.height, 0, data) &&
           out->close();
}

// Does the segment p → q cross the square |x|, |y| ≤ h of the plane z = z0 (by a margin)?
int crossesSquare(glm::dvec3 p, glm::dvec3 q, double z0, double h, double margin) {
    if ((p.z - z0) * (q.z - z0) >= 0.0) return 0;
    const double t = (z0 - p.z) / (q.z - p.z);
    const glm::dvec3 x = p + t * (q - p);
    const double m = std::max(std::abs(x.x), std::abs(x.y));
    if (m < h - margin) return 1;  // inside
    if (m > h + margin) return -1; // outside
    return 0;                      // too close to the edge to say
}

} // namespace

TEST(DeepGBuffer, PaneOverWallComposesAsFortyPercentPaneAndSixtyWall) {
    const int W = 48, H = 40;
    const DeepGBuffer deep = deepOf(paneScene(true, true), kFront, W, H);
    const std::vector<Light> lights = {pointLight({0.3f, 0.6f, 2.0f}, 3.0f)};
    ImageBuf lit, paneAlone, wallAlone;
    ASSERT_TRUE(shadeGBuffer(lit, deep, {lights}, {})) << lit.geterror();
    ASSERT_TRUE(shadeGBuffer(paneAlone, flatOf(paneScene(false, true), kFront, W, H), {lights}));
    ASSERT_TRUE(shadeGBuffer(wallAlone, flatOf(paneScene(true, false), kFront, W, H), {lights}));
    int two = 0, one = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int n = deep.samples(x, y);
            const float* c = px(lit, x, y);
            const float* p = px(paneAlone, x, y);
            const float* w = px(wallAlone, x, y);
            if (p[3] > 0.0f) {
                ASSERT_EQ(n, 2) << x << "," << y;
                ++two;
                EXPECT_FLOAT_EQ(deep.sample(x, y, 0)[0], 0.4f); // A of the pane, front
                EXPECT_LT(deep.sample(x, y, 0)[1], deep.sample(x, y, 1)[1]);
                for (int k = 0; k < 3; ++k)
                    EXPECT_NEAR(c[k], 0.4f * p[k] + 0.6f * w[k], 1e-5f * (1.0f + w[k]));
                EXPECT_FLOAT_EQ(c[3], 1.0f);
            } else if (w[3] > 0.0f) {
                ASSERT_EQ(n, 1);
                ++one;
                for (int k = 0; k < 4; ++k)
                    EXPECT_FLOAT_EQ(c[k], w[k]);
            }
        }
    EXPECT_GT(two, 200);
    EXPECT_GT(one, 200);
}

TEST(DeepGBuffer, PanesShadowIsSixtyPercentOfTheLight) {
    // The wall lit through the pane by a point light in front of both: wall pixels whose
    // segment to the light crosses the pane get exactly 0.6 of the unshadowed light, the others
    // all of it.
    const Scene scene = paneScene(true, true);
    const RayCaster caster(scene);
    ASSERT_TRUE(caster.ok());
    const glm::vec3 lightPos(-0.4f, 0.3f, 1.5f);
    const std::vector<Light> lights = {pointLight(lightPos, 3.0f)};
    // Seen from aside, so that the shadow falls on wall pixels not behind the pane.
    const Camera camera = Camera::lookAt({-1.2, -0.6, 3.0}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.8);
    const int W = 64, H = 64;
    const DeepGBuffer deep = deepOf(scene, camera, W, H);
    LightingParams noShadows;
    noShadows.shadows = false;
    ImageBuf shadowed, open;
    ASSERT_TRUE(shadeGBuffer(shadowed, deep, {lights, &caster}, {}, {}, 0, nullptr));
    ASSERT_TRUE(shadeGBuffer(open, deep, {lights, &caster}, noShadows, {}, 0, nullptr));
    const gbuffer::Layout layout = [&] {
        gbuffer::Layout l;
        std::string missing;
        EXPECT_TRUE(gbuffer::findLayout(deep.spec, l, missing));
        return l;
    }();
    int inShadow = 0, outside = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            if (deep.samples(x, y) != 1) continue; // the wall alone
            const float* s = deep.sample(x, y, 0);
            const glm::dvec3 P(s[layout.position], s[layout.position + 1], s[layout.position + 2]);
            const int crosses = crossesSquare(P, glm::dvec3(lightPos), 0.5, 0.5, 0.01);
            const float* a = px(shadowed, x, y);
            const float* b = px(open, x, y);
            if (crosses == 1) {
                ++inShadow;
                for (int k = 0; k < 3; ++k)
                    EXPECT_NEAR(a[k], 0.6f * b[k], 1e-6f + 1e-6f * b[k]) << x << "," << y;
            } else if (crosses == -1) {
                ++outside;
                for (int k = 0; k < 3; ++k)
                    EXPECT_EQ(a[k], b[k]) << x << "," << y;
            }
        }
    EXPECT_GT(inShadow, 100);
    EXPECT_GT(outside, 100);
}

TEST(DeepGBuffer, MaskCardShowsAndCastsItsHoles) {
    // A card over the wall whose texture is a 4 × 4 checker of alpha 1 and 0 (cutoff 0.5): a
    // pixel sees the card where the checker is solid and the wall through the holes, and the
    // card's shadow on the wall has the same holes.
    Scene scene = paneScene(true, false);
    Texture checker;
    checker.name = "checker";
    checker.width = checker.height = 4;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const float a = (x + y) % 2 == 0 ? 1.0f : 0.0f;
            checker.rgba.insert(checker.rgba.end(), {1.0f, 1.0f, 1.0f, a});
        }
    scene.textures.push_back(checker);
    Material card = lambert("card", glm::vec3(0.9f, 0.2f, 0.2f));
    card.alphaMode = AlphaMode::Mask;
    card.alphaCutoff = 0.5f;
    card.baseColorTexture.texture = 0;
    scene.materials.push_back(card);
    scene.objectNames.push_back("card");
    addQuad(scene, {-0.5f, -0.5f, 0.5f}, {0.5f, -0.5f, 0.5f}, {0.5f, 0.5f, 0.5f},
            {-0.5f, 0.5f, 0.5f}, 2, 2);
    // The checker cell of a point of the card (u right, v down the image; texel centres
    // bilinear, so only cell centres are asked about).
    auto solidAt = [](double x, double y) {
        const int cx = int(std::floor((x + 0.5) * 4.0)), cy = int(std::floor((0.5 - y) * 4.0));
        return (cx + cy) % 2 == 0;
    };
    auto nearCellCentre = [](double x, double y) {
        const double fx = (x + 0.5) * 4.0 - std::floor((x + 0.5) * 4.0);
        const double fy = (0.5 - y) * 4.0 - std::floor((0.5 - y) * 4.0);
        return std::abs(fx - 0.5) < 0.2 && std::abs(fy - 0.5) < 0.2;
    };
    const int W = 64, H = 64;
    const Camera camera = Camera::lookAt({0.0, 0.0, 3.0}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.6);
    const ImageBuf g = flatOf(scene, camera, W, H);
    const int obj = g.spec().channelindex("id.object");
    int onCard = 0, hole = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            // Where the pixel's ray meets the card's plane.
            const Ray r = camera.primaryRay(x, y, W, H);
            const double t = (0.5 - r.origin.z) / r.direction.z;
            const glm::dvec3 p = r.origin + t * r.direction;
            if (std::abs(p.x) > 0.5 || std::abs(p.y) > 0.5 || !nearCellCentre(p.x, p.y)) continue;
            const float id = px(g, x, y)[obj];
            if (solidAt(p.x, p.y)) {
                EXPECT_EQ(id, 3.0f) << x << "," << y;
                ++onCard;
            } else {
                EXPECT_EQ(id, 1.0f) << x << "," << y;
                ++hole;
            }
        }
    EXPECT_GT(onCard, 20);
    EXPECT_GT(hole, 20);
    // The shadow: a light straight in front, segments from the wall to it cross the card.
    const RayCaster caster(scene);
    const glm::dvec3 light(0.0, 0.0, 2.0);
    int dark = 0, lit = 0;
    for (int i = 0; i < 1600; ++i) {
        const glm::dvec3 P(-0.9 + 1.8 * ((i % 40) + 0.5) / 40.0,
                           -0.9 + 1.8 * ((i / 40) + 0.5) / 40.0, 1e-4);
        // The segment's point on the card's plane.
        const double t = (0.5 - P.z) / (light.z - P.z);
        const glm::dvec3 c = P + t * (light - P);
        if (std::abs(c.x) > 0.5 || std::abs(c.y) > 0.5 || !nearCellCentre(c.x, c.y)) continue;
        const glm::vec3 d(glm::normalize(light - P));
        const float through = caster.transmittance(glm::vec3(P), d, float(glm::length(light - P)));
        if (solidAt(c.x, c.y)) {
            EXPECT_EQ(through, 0.0f);
            ++dark;
        } else {
            EXPECT_EQ(through, 1.0f);
            ++lit;
        }
    }
    EXPECT_GT(dark, 20);
    EXPECT_GT(lit, 20);
}

TEST(DeepGBuffer, CulledEqualsBruteForcePerSample) {
    // Many small lights around the pane and the wall: the tile lists, bounded by every
    // sample's depth, give each sample the lights brute force gives it.
    const Scene scene = paneScene(true, true);
    std::vector<Light> lights;
    for (int i = 0; i < 40; ++i) {
        Light l = pointLight(
            {-1.0f + 0.05f * float(i), 0.4f * std::sin(float(i)), 0.2f + 0.03f * float(i % 17)},
            0.2f);
        l.range = 0.5f;
        lights.push_back(l);
    }
    const DeepGBuffer deep = deepOf(scene, kFront, 64, 48);
    LightingParams brute;
    brute.bruteForce = true;
    ImageBuf culled, reference;
    std::vector<float> culledSamples, referenceSamples;
    ASSERT_TRUE(shadeGBuffer(culled, deep, {lights}, {}, {}, 0, nullptr, &culledSamples));
    ASSERT_TRUE(shadeGBuffer(reference, deep, {lights}, brute, {}, 0, nullptr, &referenceSamples));
    ASSERT_EQ(culledSamples.size(), referenceSamples.size());
    double worst = 0.0;
    for (size_t i = 0; i < culledSamples.size(); ++i)
        worst = std::max(worst, double(std::abs(culledSamples[i] - referenceSamples[i])));
    EXPECT_LT(worst, 1e-5);
    const auto stats = OIIO::ImageBufAlgo::compare(culled, reference, 1e-5f, 1e-5f);
    EXPECT_EQ(stats.nfail, 0u);
}

TEST(DeepGBuffer, DoesNotDependOnTheThreadCount) {
    const Scene scene = paneScene(true, true);
    const RayCaster caster(scene);
    const std::vector<Light> lights = {pointLight({-0.4f, 0.3f, 1.5f}, 3.0f)};
    LightingParams p;
    p.aoSamples = 8;
    p.aoDistance = 0.5f;
    const DeepGBuffer one = deepOf(scene, kFront, 40, 32, 1);
    const DeepGBuffer two = deepOf(scene, kFront, 40, 32, 2);
    ASSERT_EQ(one.first, two.first);
    ASSERT_EQ(one.values, two.values);
    ImageBuf a, b;
    ASSERT_TRUE(shadeGBuffer(a, one, {lights, &caster}, p, {}, 1));
    ASSERT_TRUE(shadeGBuffer(b, one, {lights, &caster}, p, {}, 2));
    EXPECT_EQ(std::memcmp(a.localpixels(), b.localpixels(), a.spec().image_bytes()), 0);
}

TEST(DeepGBuffer, BandsReadAndLitEqualTheWholeFrame) {
    // What dhdr-light does to bound memory: the file read a band of rows at a time and each
    // band lit with params.frame; pixels, per-sample colours and stats equal the whole frame's
    // bit for bit (shadows, AO and many culled lights included).
    const Scene scene = paneScene(true, true);
    const RayCaster caster(scene);
    std::vector<Light> lights = {pointLight({-0.4f, 0.3f, 1.5f}, 3.0f)};
    for (int i = 0; i < 20; ++i) {
        Light l = pointLight({-1.0f + 0.1f * float(i), 0.3f * std::sin(float(i)), 0.3f}, 0.2f);
        l.range = 0.6f;
        lights.push_back(l);
    }
    const DeepGBuffer deep = deepOf(scene, kFront, 40, 100);
    const std::string path = (std::filesystem::temp_directory_path() / "dhdr_bands.exr").string();
    ASSERT_TRUE(writeDeep(path, deep));
    DeepGBuffer whole;
    std::string error;
    ASSERT_TRUE(readDeepGBuffer(path, 0, whole, error)) << error;
    ASSERT_GT(whole.totalSamples(), size_t(40 * 100)); // the pane's pixels hold two samples
    LightingParams p;
    p.aoSamples = 4;
    p.aoDistance = 0.5f;
    ImageBuf reference;
    std::vector<float> referenceSamples;
    LightingStats referenceStats;
    ASSERT_TRUE(shadeGBuffer(reference, whole, {lights, &caster}, p, {}, 0, &referenceStats,
                             &referenceSamples));

    DeepGBufferReader reader;
    ASSERT_TRUE(reader.open(path, 0, error)) << error;
    EXPECT_EQ(reader.spec().height, 100);
    LightingParams banded = p;
    banded.frame = OIIO::get_roi(reader.spec());
    const int rows = 2 * p.tileSize; // 32: bands of 32, 32, 32 and 4 rows
    std::vector<float> samples;
    LightingStats stats;
    size_t at = 0;
    for (int y = 0; y < 100; y += rows) {
        DeepGBuffer band;
        ASSERT_TRUE(reader.read(y, y + rows, band, error)) << error;
        ASSERT_EQ(band.spec.y, y);
        ASSERT_EQ(band.spec.height, std::min(rows, 100 - y));
        // The band's samples are the whole file's rows.
        const size_t first = whole.first[whole.pixel(0, y)];
        ASSERT_TRUE(
            std::equal(band.values.begin(), band.values.end(),
                       whole.values.begin() + std::ptrdiff_t(first * size_t(band.spec.nchannels))));
        ImageBuf lit;
        LightingStats bandStats;
        ASSERT_TRUE(shadeGBuffer(lit, band, {lights, &caster}, banded, {}, 0, &bandStats, &samples))
            << lit.geterror();
        stats += bandStats;
        for (int yy = lit.spec().y; yy < lit.spec().y + lit.spec().height; ++yy)
            for (int x = 0; x < 40; ++x)
                for (int c = 0; c < 4; ++c)
                    ASSERT_EQ(px(lit, x, yy)[c], px(reference, x, yy)[c]) << x << "," << yy;
        ASSERT_TRUE(std::equal(samples.begin(), samples.end(),
                               referenceSamples.begin() + std::ptrdiff_t(at)));
        at += samples.size();
    }
    EXPECT_EQ(at, referenceSamples.size());
    EXPECT_EQ(stats.coveredPixels, referenceStats.coveredPixels);
    EXPECT_EQ(stats.shadowRays, referenceStats.shadowRays);
    EXPECT_EQ(stats.aoRays, referenceStats.aoRays);
    std::filesystem::remove(path);
}

TEST(DeepExr, RowsWhoseOffsetsPassTwoToTheThirtyOneAreWrittenAndRead) {
    // OpenImageIO 2.4.7 crashes writing or reading deep rows where y × width × channels passes
    // 2^31 (a 16K deep G-buffer past row ~5,000). The same offsets with a small file: 128 rows
    // of 4096 × 32 channels whose data window starts at row 20000 (20000 × 4096 × 32 > 2^31).
    // Written and read back through deep_exr.h, the values are the ones written.
    const int W = 4096, nch = 32, first = 20064, H = 20128;
    OIIO::ImageSpec spec(W, 128, nch, OIIO::TypeDesc::FLOAT);
    spec.y = 20000;
    spec.deep = true;
    spec.channelnames.clear();
    for (int c = 0; c < nch; ++c)
        spec.channelnames.push_back(c == 0 ? "Z" : "c" + std::to_string(c));
    spec.attribute("dhdr:test", "large");
    const std::string path =
        (std::filesystem::temp_directory_path() / "dhdr_deep_large.exr").string();
    auto value = [](int x, int y, int c) { return float(x) + 0.5f * float(y % 7) + float(c); };
    {
        DeepScanlineWriter writer;
        std::string error;
        ASSERT_TRUE(writer.open(path, spec, error)) << error;
        for (int y = spec.y; y < H; y += 64) {
            OIIO::DeepData rows;
            rows.init(int64_t(W) * 64, nch, {OIIO::TypeDesc::FLOAT}, spec.channelnames);
            if (y >= first) {
                std::vector<unsigned> counts(size_t(W) * 64, 0);
                for (size_t p = 0; p < counts.size(); p += 16)
                    counts[p] = 1;
                rows.set_all_samples(counts);
                for (size_t p = 0; p < counts.size(); p += 16)
                    for (int c = 0; c < nch; ++c)
                        rows.set_deep_value(int64_t(p), c, 0, value(int(p % W), y + int(p / W), c));
            }
            ASSERT_TRUE(writer.write(y, y + 64, rows, error)) << error;
        }
        ASSERT_TRUE(writer.close(error)) << error;
    }
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    const OIIO::ImageSpec read = in->spec();
    EXPECT_EQ(read.get_string_attribute("dhdr:test"), "large");
    DeepScanlineReader reader;
    std::string error;
    ASSERT_TRUE(reader.open(path, 0, read, error)) << error;
    OIIO::DeepData rows;
    ASSERT_TRUE(reader.read(first, H, rows, error)) << error;
    const int z = read.channelindex("Z"), c5 = read.channelindex("c5");
    long long checked = 0;
    for (int64_t p = 0; p < rows.pixels(); ++p) {
        ASSERT_EQ(rows.samples(p), p % 16 == 0 ? 1 : 0) << p;
        if (p % 16 != 0) continue;
        const int x = int(p % W), y = first + int(p / W);
        ASSERT_EQ(rows.deep_value(p, z, 0), value(x, y, 0));
        ASSERT_EQ(rows.deep_value(p, c5, 0), value(x, y, 5));
        ++checked;
    }
    EXPECT_EQ(checked, W * 64 / 16);
    std::filesystem::remove(path);
}

TEST(DeepGBuffer, FileReadBackWithOpenEXRsDeepReader) {
    // Written as dhdr-gbuffer writes it, read back by OpenEXR's own deep scanline reader:
    // the sample counts, Z = ZBack, front to back.
    const DeepGBuffer deep = deepOf(paneScene(true, true), kFront, 32, 24);
    const std::string path =
        (std::filesystem::temp_directory_path() / "dhdr_deep_readback.exr").string();
    ASSERT_TRUE(writeDeep(path, deep));
    Imf::DeepScanLineInputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    ASSERT_EQ(w, 32);
    ASSERT_EQ(h, 24);
    std::vector<unsigned> counts(size_t(w) * size_t(h));
    Imf::DeepFrameBuffer fb;
    fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, reinterpret_cast<char*>(counts.data()),
                                         sizeof(unsigned), sizeof(unsigned) * size_t(w)));
    std::vector<float*> z(counts.size()), zBack(counts.size());
    fb.insert("Z", Imf::DeepSlice(Imf::FLOAT, reinterpret_cast<char*>(z.data()), sizeof(float*),
                                  sizeof(float*) * size_t(w), sizeof(float)));
    fb.insert("ZBack", Imf::DeepSlice(Imf::FLOAT, reinterpret_cast<char*>(zBack.data()),
                                      sizeof(float*), sizeof(float*) * size_t(w), sizeof(float)));
    file.setFrameBuffer(fb);
    file.readPixelSampleCounts(dw.min.y, dw.max.y);
    std::vector<float> storeZ, storeBack;
    size_t total = 0;
    for (unsigned c : counts)
        total += c;
    storeZ.resize(total);
    storeBack.resize(total);
    for (size_t p = 0, at = 0; p < counts.size(); at += counts[p], ++p) {
        z[p] = storeZ.data() + at;
        zBack[p] = storeBack.data() + at;
    }
    file.readPixels(dw.min.y, dw.max.y);
    EXPECT_EQ(total, deep.totalSamples());
    int twos = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t p = size_t(y) * size_t(w) + size_t(x);
            ASSERT_EQ(int(counts[p]), deep.samples(x, y));
            for (unsigned k = 0; k < counts[p]; ++k) {
                EXPECT_EQ(z[p][k], zBack[p][k]);
                EXPECT_EQ(z[p][k], deep.sample(x, y, int(k))[1]);
                if (k > 0) {
                    EXPECT_LT(z[p][k - 1], z[p][k]);
                }
            }
            twos += counts[p] == 2;
        }
    EXPECT_GT(twos, 50);
    std::filesystem::remove(path);
}

TEST(DeepGBuffer, SamplesInAnyOrderAreSortedAndVolumesRejected) {
    // Someone else's file with each pixel's samples back to front: read front to back, and lit
    // to the same picture. A sample with ZBack > Z is a volume: a clear error.
    const DeepGBuffer deep = deepOf(paneScene(true, true), kFront, 24, 20);
    const std::string dir = std::filesystem::temp_directory_path().string();
    auto write = [&](const std::string& path, bool reverse, bool volume) {
        DeepGBuffer shuffled = deep;
        const size_t nch = size_t(deep.spec.nchannels);
        for (size_t p = 0; p + 1 < deep.first.size(); ++p) {
            const size_t a = deep.first[p], b = deep.first[p + 1];
            for (size_t k = a; k < b; ++k) {
                const size_t from = reverse ? a + (b - 1 - k) : k;
                std::copy(&deep.values[from * nch], &deep.values[from * nch] + nch,
                          &shuffled.values[k * nch]);
                if (volume) shuffled.values[k * nch + 2] += 0.1f;
            }
        }
        ASSERT_TRUE(writeDeep(path, shuffled));
    };
    const std::string ordered = dir + "/dhdr_deep_ordered.exr",
                      reversed = dir + "/dhdr_deep_reversed.exr",
                      volume = dir + "/dhdr_deep_volume.exr";
    write(ordered, false, false);
    write(reversed, true, false);
    write(volume, false, true);
    DeepGBuffer a, b, c;
    std::string error;
    ASSERT_TRUE(readDeepGBuffer(ordered, 0, a, error)) << error;
    ASSERT_TRUE(readDeepGBuffer(reversed, 0, b, error)) << error;
    EXPECT_EQ(a.first, b.first);
    EXPECT_EQ(a.values, b.values);
    const std::vector<Light> lights = {pointLight({0.3f, 0.6f, 2.0f}, 3.0f)};
    ImageBuf la, lb;
    ASSERT_TRUE(shadeGBuffer(la, a, {lights}));
    ASSERT_TRUE(shadeGBuffer(lb, b, {lights}));
    EXPECT_EQ(OIIO::ImageBufAlgo::compare(la, lb, 0.0f, 0.0f).nfail, 0u);
    EXPECT_FALSE(readDeepGBuffer(volume, 0, c, error));
    EXPECT_NE(error.find("ZBack > Z"), std::string::npos) << error;
    for (const std::string& p : {ordered, reversed, volume})
        std::filesystem::remove(p);
}

TEST(GBufferContract, DocsListTheTable) {
    // docs/gbuffer.md's channel table holds exactly the rows of gbuffer::kContract: names,
    // file type, what a reader needs and the meaning.
    std::ifstream in(std::string(DHDR_TESTDATA) + "/../docs/gbuffer.md");
    ASSERT_TRUE(in) << "docs/gbuffer.md";
    std::vector<std::string> rows;
    bool table = false;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("| channels | file type | reader | meaning |", 0) == 0)
            table = true;
        else if (table && line.rfind("| `", 0) == 0)
            rows.push_back(line);
        else if (table && !rows.empty() && line.rfind("|", 0) != 0)
            break;
    }
    std::vector<std::string> expected;
    for (const gbuffer::ContractChannel& c : gbuffer::kContract) {
        std::string names;
        for (int i = 0; i < c.components; ++i)
            names += (i ? " " : "") + std::string(c.names[i]);
        const char* type = c.type == gbuffer::FileType::Float  ? "float"
                           : c.type == gbuffer::FileType::Uint ? "uint"
                                                               : "half";
        const char* need = c.need == gbuffer::Need::Required   ? "required"
                           : c.need == gbuffer::Need::Optional ? "optional"
                           : c.need == gbuffer::Need::WhenUsed ? "when used"
                                                               : "deep only";
        expected.push_back("| `" + names + "` | " + type + " | " + need + " | " + c.meaning + " |");
    }
    EXPECT_EQ(rows, expected);
    // And the writers follow it: the flat names are the table's without ZBack, in its order.
    for (unsigned uses = 0; uses <= gbuffer::kAllUses; ++uses) {
        std::vector<std::string> deep = gbuffer::deepChannelNames(uses),
                                 flat = gbuffer::channelNames(uses);
        for (const char* deepOnly :
             {gbuffer::kDepthBack, gbuffer::kSampleId, gbuffer::kSampleWeight})
            if (const auto it = std::find(deep.begin(), deep.end(), std::string(deepOnly));
                it != deep.end())
                deep.erase(it);
        EXPECT_EQ(deep, flat);
        // The rays' channels only in deep G-buffers of several rays a pixel.
        const std::vector<std::string> all = gbuffer::deepChannelNames(uses);
        EXPECT_EQ(std::count(all.begin(), all.end(), std::string(gbuffer::kSampleWeight)),
                  uses & gbuffer::kUsesPixelSamples ? 1 : 0);
        EXPECT_TRUE(gbuffer::isWrittenLayout(flat, false)) << uses;
        // The WhenUsed channels only when asked for.
        EXPECT_EQ(std::count(flat.begin(), flat.end(), std::string(gbuffer::kOcclusion)),
                  uses & gbuffer::kUsesOcclusion ? 1 : 0);
        EXPECT_EQ(std::count(flat.begin(), flat.end(), std::string(gbuffer::kSpecularWeight)),
                  uses & gbuffer::kUsesSpecular ? 1 : 0);
    }
    EXPECT_EQ(gbuffer::channelFormats(gbuffer::deepChannelNames()).size(),
              gbuffer::deepChannelNames().size());
}

TEST(DeepGBuffer, MaterialsReadTheirAlphaModes) {
    // glTF: alphaMode and alphaCutoff as the file says; OBJ/MTL: d, or 1 − Tr, below 1 blends.
    Scene gltf;
    std::string error;
    ASSERT_TRUE(loadScene(std::string(DHDR_TESTDATA) + "/cornell_glass.gltf", gltf, error))
        << error;
    auto find = [](const Scene& s, const std::string& name) -> const Material* {
        for (const Material& m : s.materials)
            if (m.name == name) return &m;
        return nullptr;
    };
    ASSERT_TRUE(find(gltf, "glass") && find(gltf, "card") && find(gltf, "white"));
    EXPECT_EQ(find(gltf, "glass")->alphaMode, AlphaMode::Blend);
    EXPECT_FLOAT_EQ(find(gltf, "glass")->alpha, 0.4f);
    EXPECT_EQ(find(gltf, "card")->alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(find(gltf, "card")->alphaCutoff, 0.5f);
    EXPECT_EQ(find(gltf, "white")->alphaMode, AlphaMode::Opaque);

    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "dhdr_obj_alpha";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "a.mtl") << "newmtl solid\nKd 0.8 0.8 0.8\n\n"
                                 << "newmtl smoke\nKd 0.5 0.5 0.5\nd 0.3\n\n"
                                 << "newmtl tinted\nKd 0.2 0.4 0.8\nTr 0.25\n";
    std::ofstream(dir / "a.obj") << "mtllib a.mtl\n"
                                 << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                 << "usemtl solid\nf 1 2 3\nusemtl smoke\nf 1 3 4\n"
                                 << "usemtl tinted\nf 2 3 4\n";
    Scene obj;
    ASSERT_TRUE(loadScene((dir / "a.obj").string(), obj, error)) << error;
    ASSERT_TRUE(find(obj, "solid") && find(obj, "smoke") && find(obj, "tinted"));
    EXPECT_EQ(find(obj, "solid")->alphaMode, AlphaMode::Opaque);
    EXPECT_EQ(find(obj, "smoke")->alphaMode, AlphaMode::Blend);
    EXPECT_FLOAT_EQ(find(obj, "smoke")->alpha, 0.3f);
    EXPECT_EQ(find(obj, "tinted")->alphaMode, AlphaMode::Blend);
    EXPECT_FLOAT_EQ(find(obj, "tinted")->alpha, 0.75f);
    std::filesystem::remove_all(dir);
}

// A deep file whose sample count table claims 10⁸ samples a pixel (patched into an honest
// uncompressed file): the reader refuses it, naming the claim, before allocating 6 GB.
TEST(DeepExr, SampleCountsBeyondWhatTheFileCanHoldAreRefused) {
    const int W = 16;
    const std::string path =
        (std::filesystem::temp_directory_path() / "dhdr_deep_claims.exr").string();
    {
        Imf::Header header(W, 1);
        header.compression() = Imf::NO_COMPRESSION;
        header.setType(Imf::DEEPSCANLINE);
        header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
        Imf::DeepScanLineOutputFile file(path.c_str(), header);
        std::vector<unsigned> counts(W, 1);
        std::vector<float> z(W, 2.0f);
        std::vector<float*> zp(W);
        for (int x = 0; x < W; ++x)
            zp[size_t(x)] = &z[size_t(x)];
        Imf::DeepFrameBuffer fb;
        fb.insertSampleCountSlice(
            Imf::Slice(Imf::UINT, reinterpret_cast<char*>(counts.data()), sizeof(unsigned), 0));
        fb.insert("Z", Imf::DeepSlice(Imf::FLOAT, reinterpret_cast<char*>(zp.data()),
                                      sizeof(float*), 0, sizeof(float)));
        file.setFrameBuffer(fb);
        file.writePixels(1);
    }
    // The chunk's count table: cumulative counts 1, 2, …, W as little-endian int32.
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    std::string table, claim;
    for (std::int32_t x = 1; x <= W; ++x) {
        const std::int32_t c = x * 100000000;
        table.append(reinterpret_cast<const char*>(&x), 4);
        claim.append(reinterpret_cast<const char*>(&c), 4);
    }
    const size_t at = bytes.find(table);
    ASSERT_NE(at, std::string::npos);
    bytes.replace(at, claim.size(), claim);
    std::ofstream(path, std::ios::binary) << bytes;

    OIIO::ImageSpec spec(W, 1, 1, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"Z"};
    spec.deep = true;
    DeepScanlineReader reader;
    std::string error;
    ASSERT_TRUE(reader.open(path, 0, spec, error)) << error;
    OIIO::DeepData out;
    EXPECT_FALSE(reader.read(0, 1, out, error));
    EXPECT_NE(error.find("claim"), std::string::npos) << error;
    std::filesystem::remove(path);
}
