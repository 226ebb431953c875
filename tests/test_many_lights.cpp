// Many area lights sharing a budget of shadow rays (sharedLightVisibility,
// docs/lighting.md "Many emitters") against each light's own rays: the same light in
// expectation (Monte Carlo in double over many seeds), exact where nothing or everything is in
// the way, the same bits for any thread count, and no more noise in a frame than the
// exhaustive path's.
#include "direct/direct_lighting.h"
#include "scene_builder.h"

#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/denoise/denoise.h>
#include <dhdr/deferred/direct/shadows.h>
#include <dhdr/deferred/lights/emissive_lights.h>
#include <dhdr/deferred/lights/light.h>
#include <gtest/gtest.h>

using namespace dhdr;
using namespace dhdr::test;

namespace {

// A floor, a sheet at height 0.3 over x < 0 that shadows part of it, and 12 small lights at
// height 0.8 of several colours and families: 8 glowing quads (emissive meshes, seen from both
// sides), 2 spheres and 2 rectangles facing down.
struct ManyLightScene {
    Scene scene = emptyScene();
    std::vector<Light> lights;

    ManyLightScene() {
        addFloor(scene, 4.0f);
        addQuad(scene, {-4, 0.3f, -4}, {-4, 0.3f, 4}, {0, 0.3f, 4}, {0, 0.3f, -4});
        const glm::vec3 colours[4] = {
            {1.0f, 0.2f, 0.1f}, {0.1f, 1.0f, 0.2f}, {0.2f, 0.3f, 1.0f}, {1.0f, 1.0f, 0.8f}};
        for (int i = 0; i < 8; ++i) {
            Material glow;
            glow.name = "glow" + std::to_string(i);
            glow.baseColor = glm::vec3(0.0f);
            glow.emission = colours[i % 4] * (2.0f + float(i));
            scene.materials.push_back(glow);
            const float x = -0.9f + 0.25f * float(i), z = i % 2 ? 0.3f : -0.3f, s = 0.04f;
            addQuad(scene, {x - s, 0.8f, z - s}, {x + s, 0.8f, z - s}, {x + s, 0.8f, z + s},
                    {x - s, 0.8f, z + s}, int(scene.materials.size()) - 1);
        }
        lights = emissiveLights(scene);
        for (int i = 0; i < 4; ++i) {
            Light l;
            l.type = i < 2 ? LightType::Sphere : LightType::Rectangle;
            l.position = {i % 2 ? 0.6f : -0.6f, 0.8f, i < 2 ? 0.6f : -0.6f};
            l.radius = 0.05f;
            l.width = l.height = 0.1f;
            l.direction = {0.0f, -1.0f, 0.0f};
            l.up = {0.0f, 0.0f, 1.0f};
            l.intensity = 0.05f;
            l.color = colours[(i + 1) % 4];
            lights.push_back(l);
        }
    }
};

// At 96 floor points in and around the sheet's shadow: the mean of 400 seeds of `budget`
// shared rays against Σ c_i V_i with each light's own 4096 rays, off by no more than 4 standard
// errors of the mean and `bias` of the point's unshadowed light.
void sharedRaysAgainstOwnRays(int budget, double bias) {
    const ManyLightScene m;
    ASSERT_EQ(m.lights.size(), 12u);
    const RayCaster caster(m.scene);
    PbrSurface surface;
    surface.baseColor = glm::vec3(0.7f);
    surface.roughness = 0.4f;
    const glm::vec3 up(0.0f, 1.0f, 0.0f);
    std::vector<const Light*> pointers;
    for (const Light& l : m.lights)
        pointers.push_back(&l);
    double sumReference = 0.0, sumShared = 0.0, sumOpen = 0.0, worst = 0.0;
    int partial = 0;
    for (int i = 0; i < 96; ++i) {
        const glm::vec3 P(-1.2f + 0.025f * float(i), 0.0f, 0.1f * float(i % 7) - 0.3f);
        const SurfacePoint at{P, up, 1e-6f};
        const glm::vec3 V = glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f));
        std::vector<glm::vec3> c;
        glm::dvec3 reference(0.0), open(0.0);
        for (std::uint32_t k = 0; k < m.lights.size(); ++k) {
            c.push_back(shadeLight(m.lights[k], surface, P, up, V));
            const float v =
                lightVisibility(m.lights[k], at, up, sampleSeed(i, 0, k, 1), 4096, caster);
            reference += glm::dvec3(c.back()) * double(v);
            open += glm::dvec3(c.back());
        }
        // The mean and its standard error over the seeds.
        glm::dvec3 shared(0.0), squares(0.0);
        const int seeds = 400;
        for (int s = 0; s < seeds; ++s) {
            const glm::dvec3 x(sharedLightVisibility(pointers.data(), c.data(), c.size(), at, up,
                                                     sampleSeed(i, s, -5, 1), budget, caster));
            shared += x;
            squares += x * x;
        }
        shared /= double(seeds);
        const glm::dvec3 error =
            glm::sqrt(glm::max(squares / double(seeds) - shared * shared, 0.0) / double(seeds));
        for (int ch = 0; ch < 3; ++ch) {
            ASSERT_GT(open[ch], 0.0);
            // Off by more than the mean's noise (4 standard errors) and the ratio estimators'
            // own bias at a few rays (0.5 % of the unshadowed light).
            const double off =
                std::abs(shared[ch] - reference[ch]) / (4.0 * error[ch] + bias * open[ch]);
            worst = std::max(worst, off);
        }
        const double r = reference.r + reference.g + reference.b, o = open.r + open.g + open.b;
        partial += r > 0.02 * o && r < 0.98 * o;
        sumReference += r;
        sumShared += shared.r + shared.g + shared.b;
        sumOpen += o;
    }
    std::printf("shared %.6f, own rays %.6f, unshadowed %.6f; worst point off by %.3f of "
                "its allowance; %d partly shadowed points\n",
                sumShared, sumReference, sumOpen, worst, partial);
    EXPECT_GT(partial, 20); // the comparison is about shadows, not open floor
    EXPECT_LT(sumReference, 0.9 * sumOpen);
    EXPECT_NEAR(sumShared / sumReference, 1.0, 0.003);
    EXPECT_LT(worst, 1.0);
}

// Shades `gbuf` in strips of `rows` rows, each cut with the denoiser's reach of rows above and
// below, as dhdr-light reads them.
ImageBuf shadeInStrips(const ImageBuf& gbuf, const LightingInputs& inputs, LightingParams params,
                       int rows) {
    const OIIO::ROI frame = gbuf.roi();
    params.frame = frame;
    ImageBuf out(OIIO::ImageSpec(frame.width(), frame.height(), 4, OIIO::TypeDesc::FLOAT));
    for (int y = frame.ybegin; y < frame.yend; y += rows) {
        const OIIO::ROI own(frame.xbegin, frame.xend, y, std::min(frame.yend, y + rows));
        const OIIO::ROI band(frame.xbegin, frame.xend, std::max(frame.ybegin, y - kDenoiseReach),
                             std::min(frame.yend, own.yend + kDenoiseReach), 0, 1, 0,
                             gbuf.nchannels());
        ImageBuf strip = OIIO::ImageBufAlgo::cut(gbuf, band);
        strip.set_origin(band.xbegin, band.ybegin);
        ImageBuf lit;
        EXPECT_TRUE(shadeGBuffer(lit, strip, inputs, params, own, 2)) << lit.geterror();
        EXPECT_TRUE(OIIO::ImageBufAlgo::paste(
            out, 0, 0, 0, 0, lit,
            OIIO::ROI(own.xbegin, own.xend, own.ybegin, own.yend, 0, 1, 0, 4)))
            << out.geterror();
    }
    return out;
}

} // namespace

// With 32 rays every one of the 12 lights gets one, each its own ratio estimator: as biased as
// each light's own (0.5 % allowed for the ratio estimators at a few rays). With 8, lights few
// rays pick lean on the others' ratio: a bias of up to 1.5 % of a point's light (seen: 1.1 %
// at 4 standard errors), 0.1 % over the points.
TEST(ManyLights, SharedRaysConvergeToEachLightsOwnRays) {
    for (const int budget : {32, 8}) {
        SCOPED_TRACE(budget);
        sharedRaysAgainstOwnRays(budget, budget == 32 ? 0.005 : 0.015);
    }
}

// Where every ray gets through, the unshadowed sum exactly; under the sheet's umbra of every
// light, exactly 0.
TEST(ManyLights, OpenAndHiddenPointsAreExact) {
    const ManyLightScene m;
    const RayCaster caster(m.scene);
    PbrSurface surface;
    const glm::vec3 up(0.0f, 1.0f, 0.0f), V(0.0f, 1.0f, 0.0f);
    std::vector<const Light*> pointers;
    for (const Light& l : m.lights)
        pointers.push_back(&l);
    for (const glm::vec3 P : {glm::vec3(2.5f, 0.0f, 0.0f), glm::vec3(-3.5f, 0.0f, 0.0f)}) {
        const SurfacePoint at{P, up, 1e-6f};
        std::vector<glm::vec3> c;
        glm::vec3 open(0.0f);
        for (const Light& l : m.lights) {
            c.push_back(shadeLight(l, surface, P, up, V));
            open += c.back();
        }
        ASSERT_GT(open.g, 0.0f);
        long long rays = 0;
        const glm::vec3 shared = sharedLightVisibility(pointers.data(), c.data(), c.size(), at, up,
                                                       sampleSeed(1, 2, -5, 1), 32, caster, &rays);
        EXPECT_EQ(rays, 32);
        // The sum is taken in double in the lights' order, then rounded.
        glm::dvec3 exact(0.0);
        for (const glm::vec3& x : c)
            exact += glm::dvec3(x);
        EXPECT_EQ(shared, P.x > 0.0f ? glm::vec3(exact) : glm::vec3(0.0f)) << P.x;
    }
}

// Through the lighting pass: a frame of the 12 lights with the default budget traces fewer
// rays than each light's own 16, and has less noise against a 256-ray reference than each
// light's own rays at as many rays in all (RMS 9.74e-5 against 1.09e-4; against 1024 rays, 4
// times the cost, 9.71e-5 and 1.10e-4: the reference's own noise is a few percent of theirs); the
// same bits with 1 and 2 threads and in strips of 37 rows, and the brute-force light lists' result.
TEST(ManyLights, TheFrameHasLessNoiseThanEachLightsOwnRaysAtEqualRays) {
    const ManyLightScene m;
    const RayCaster caster(m.scene);
    const Camera camera = Camera::lookAt({0.0, 2.2, 2.2}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.9);
    const int W = 160, H = 120;
    const ImageBuf gbuf = gbufferOf(m.scene, camera, W, H);
    LightingParams p;
    ASSERT_GT(p.areaLightBudget, 0) << "the shared budget is the default";
    LightingStats sharedStats, ownStats, equalStats;
    const ImageBuf shared = shade(gbuf, m.lights, &caster, p, 2, &sharedStats);
    const ImageBuf oneThread = shade(gbuf, m.lights, &caster, p, 1);
    const ImageBuf strips = shadeInStrips(gbuf, {m.lights, &caster}, p, 37);
    p.bruteForce = true;
    const ImageBuf brute = shade(gbuf, m.lights, &caster, p, 2);
    p.bruteForce = false;
    p.areaLightBudget = 0;
    shade(gbuf, m.lights, &caster, p, 2, &ownStats);
    EXPECT_LT(sharedStats.shadowRays, ownStats.shadowRays / 2);
    // Each light's own rays, as few as give at least the shared path's rays in all.
    p.shadowSamples =
        int(std::ceil(16.0 * double(sharedStats.shadowRays) / double(ownStats.shadowRays)));
    const ImageBuf own = shade(gbuf, m.lights, &caster, p, 2, &equalStats);
    ASSERT_GE(equalStats.shadowRays, sharedStats.shadowRays);
    const int equalSamples = p.shadowSamples;
    p.shadowSamples = 256;
    const ImageBuf reference = shade(gbuf, m.lights, &caster, p, 2);
    double errShared = 0.0, errOwn = 0.0, sum = 0.0;
    int covered = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            for (int c = 0; c < 4; ++c) {
                const float v = px(shared, x, y)[c];
                ASSERT_EQ(px(oneThread, x, y)[c], v) << x << "," << y;
                ASSERT_EQ(px(strips, x, y)[c], v) << x << "," << y;
                ASSERT_NEAR(px(brute, x, y)[c], v, 1e-5f * std::max(std::abs(v), 1e-6f))
                    << x << "," << y;
            }
            if (!(px(reference, x, y)[3] > 0.0f)) continue;
            ++covered;
            for (int c = 0; c < 3; ++c) {
                const double r = px(reference, x, y)[c];
                errShared += std::pow(px(shared, x, y)[c] - r, 2);
                errOwn += std::pow(px(own, x, y)[c] - r, 2);
                sum += r;
            }
        }
    ASSERT_GT(covered, 1000);
    const double rmsShared = std::sqrt(errShared / (3 * covered)),
                 rmsOwn = std::sqrt(errOwn / (3 * covered)), mean = sum / (3 * covered);
    std::printf("RMS error: shared %.3g (%lld rays), own rays %.3g (%d a light, %lld rays); "
                "mean %.3g\n",
                rmsShared, sharedStats.shadowRays, rmsOwn, equalSamples, equalStats.shadowRays,
                mean);
    EXPECT_LT(rmsShared, rmsOwn);
    EXPECT_GT(rmsShared, 1e-3 * mean); // there is noise to compare
}

// The budget never takes rays from a light that would have them alone: with 64 samples a
// light, one light gets its 64 (the exhaustive path's bits) and two share 64, not 32.
TEST(ManyLights, TheBudgetIsAtLeastOneLightsSamples) {
    const ManyLightScene m;
    const RayCaster caster(m.scene);
    const Camera camera = Camera::lookAt({0.0, 2.2, 2.2}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.9);
    const ImageBuf gbuf = gbufferOf(m.scene, camera, 40, 30);
    LightingParams p;
    p.shadowSamples = 64;
    const std::vector<Light> one = {m.lights.back()};
    LightingStats shared, own;
    const ImageBuf a = shade(gbuf, one, &caster, p, 2, &shared);
    p.areaLightBudget = 0;
    const ImageBuf b = shade(gbuf, one, &caster, p, 2, &own);
    EXPECT_EQ(shared.shadowRays, own.shadowRays);
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            for (int c = 0; c < 4; ++c)
                ASSERT_EQ(px(a, x, y)[c], px(b, x, y)[c]) << x << "," << y;
    p.areaLightBudget = 32;
    const std::vector<Light> two = {m.lights[m.lights.size() - 2], m.lights.back()};
    LightingStats pair;
    shade(gbuf, two, &caster, p, 2, &pair);
    EXPECT_GT(pair.shadowRays, 40LL * own.shadowRays / 64); // more than 32 a reached pixel
    EXPECT_LE(pair.shadowRays, 64LL * 40 * 30);
}
