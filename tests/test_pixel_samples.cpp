// Several primary rays a pixel (GBufferParams::samples, docs/gbuffer.md "Samples and the pixel
// filter"): the filters' offsets against their closed-form distributions, which pixels take
// more rays, an edge's coverage against the filter's integral, pixels away from edges equal to
// the one-ray frame's bit for bit, the same bits for any threads and strips, and the lit
// resolve against a front-to-back composite of the lit samples read back by OpenImageIO.

#include "../libdeferred/src/render/pixel_samples.h"
#include "scene_builder.h"

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <cmath>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/render/pixel_filter.h>
#include <gtest/gtest.h>
#include <map>

using namespace dhdr;
using namespace dhdr::test;

namespace {

// The filter's cumulative distribution at x in closed form (its antiderivative), normalised.
double filterCdf(PixelFilter f, double w, double x) {
    x = std::clamp(x, -0.5 * w, 0.5 * w);
    const double a = -0.5 * w;
    switch (f) {
    case PixelFilter::Box:
        return (x - a) / w;
    case PixelFilter::Gaussian: {
        const double s = w / 6.0, edge = std::exp(-a * a / (2 * s * s));
        auto F = [&](double t) {
            return s * std::sqrt(M_PI / 2) * std::erf(t / (s * std::sqrt(2.0))) - edge * t;
        };
        return (F(x) - F(a)) / (F(-a) - F(a));
    }
    case PixelFilter::BlackmanHarris: {
        auto F = [&](double t) {
            const double u = 2 * M_PI * (t / w + 0.5), k = w / (2 * M_PI);
            return 0.35875 * t - 0.48829 * k * std::sin(u) + 0.14128 * k / 2 * std::sin(2 * u) -
                   0.01168 * k / 3 * std::sin(3 * u);
        };
        return (F(x) - F(a)) / (F(-a) - F(a));
    }
    }
    return 0.0;
}

} // namespace

TEST(PixelFilter, OffsetsFollowTheFiltersClosedForms) {
    for (const PixelFilter f :
         {PixelFilter::Box, PixelFilter::Gaussian, PixelFilter::BlackmanHarris})
        for (const float w : {1.0f, 1.5f, 3.0f}) {
            SCOPED_TRACE(int(f));
            const PixelFilterSampler sampler(f, w);
            for (int i = 0; i <= 64; ++i) {
                const float u = float(i) / 64.0f;
                const float x = sampler.offset(u);
                EXPECT_LE(std::abs(x), 0.5f * w + 1e-6f);
                // The offset at probability u has u of the filter's weight before it.
                EXPECT_NEAR(filterCdf(f, w, x), u, 2e-4) << "u " << u << " x " << x;
                EXPECT_NEAR(sampler.offset(1.0f - u), -x, 2e-4) << "symmetric";
            }
        }
}

TEST(PixelFilter, RaysAreStratifiedAndDependOnlyOnThePixelAndIndex) {
    const PixelFilterSampler sampler(PixelFilter::Box, 1.0f);
    // A box of width 1: ray k of 4 × 4 lies in its own quarter of each axis.
    for (int k = 0; k < 16; ++k) {
        const glm::vec2 o = sampler.rayOffset(7, 3, k, 4);
        EXPECT_GE(o.x, -0.5f + 0.25f * float(k % 4) - 1e-6f);
        EXPECT_LE(o.x, -0.25f + 0.25f * float(k % 4) + 1e-6f);
        EXPECT_GE(o.y, -0.5f + 0.25f * float(k / 4) - 1e-6f);
        EXPECT_LE(o.y, -0.25f + 0.25f * float(k / 4) + 1e-6f);
        EXPECT_EQ(o, sampler.rayOffset(7, 3, k, 4));
    }
    EXPECT_NE(sampler.rayOffset(7, 3, 0, 4), sampler.rayOffset(8, 3, 0, 4));
}

TEST(PixelSamples, ProbesDifferAtEdgesCreasesAndSteps) {
    ProbeHit a;
    a.hit = true;
    a.object = a.material = 1;
    a.position = {0, 0, 0};
    a.normal = {0, 0, 1};
    ProbeHit b = a;
    b.position = {1, 0, 0};
    EXPECT_FALSE(probesDiffer(a, b)); // the same plane
    ProbeHit miss;
    EXPECT_TRUE(probesDiffer(a, miss));
    EXPECT_FALSE(probesDiffer(miss, miss));
    ProbeHit other = b;
    other.object = 2;
    EXPECT_TRUE(probesDiffer(a, other));
    other = b;
    other.material = 2;
    EXPECT_TRUE(probesDiffer(a, other));
    // A crease: normals 30° apart differ, 20° do not (the points on one plane).
    for (const double deg : {20.0, 30.0}) {
        ProbeHit c = b;
        c.normal = {std::sin(glm::radians(deg)), 0, std::cos(glm::radians(deg))};
        c.position = {0, 1, 0}; // on both planes' line through a
        EXPECT_EQ(probesDiffer(a, c), deg > 25.0) << deg;
    }
    // A step in depth: 0.3 off the plane over a step of 1 differs, 0.2 does not.
    ProbeHit step = b;
    step.position = {1, 0, 0.3};
    EXPECT_TRUE(probesDiffer(a, step));
    step.position = {1, 0, 0.2};
    EXPECT_FALSE(probesDiffer(a, step));
}

namespace {

// A quad x < edge (in pixels right of the image's centre), y any, at z = 0, seen by an
// orthographic camera of 1 scene unit a pixel looking down −z: an edge of known position.
struct EdgeScene {
    Scene scene = emptyScene();
    Camera camera;
    static constexpr int kW = 64, kH = 32;
    explicit EdgeScene(float edge) {
        addQuad(scene, {-100, -100, 0}, {edge, -100, 0}, {edge, 100, 0}, {-100, 100, 0});
        camera = Camera::lookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, glm::radians(40.0));
        camera.orthographic = true;
        camera.ymag = kH / 2.0;
    }
};

DeepGBuffer deepOf(const Scene& scene, const Camera& camera, GBufferParams p, int w, int h,
                   int nthreads = 0, int cut = 0) {
    p.width = w;
    p.height = h;
    const GBufferRenderer renderer(scene, camera, p);
    EXPECT_TRUE(renderer.ok()) << renderer.error();
    DeepGBuffer out;
    if (cut <= 0) {
        EXPECT_TRUE(renderer.renderDeep(out, {}, nthreads));
        return out;
    }
    // Two strips joined, as dhdr-gbuffer writes them.
    DeepGBuffer top, bottom;
    EXPECT_TRUE(renderer.renderDeep(top, OIIO::ROI(0, w, 0, cut), nthreads));
    EXPECT_TRUE(renderer.renderDeep(bottom, OIIO::ROI(0, w, cut, h), nthreads));
    out = top;
    out.spec.height = h;
    out.first.pop_back();
    for (const std::uint32_t f : bottom.first)
        out.first.push_back(top.first.back() + f);
    out.values.insert(out.values.end(), bottom.values.begin(), bottom.values.end());
    return out;
}

float channel(const DeepGBuffer& g, int x, int y, int k, const char* name) {
    return g.sample(x, y, k)[g.spec.channelindex(name)];
}

// The share of pixel (x, y) its rays' surfaces cover (all opaque here).
double coverage(const DeepGBuffer& g, int x, int y) {
    double sum = 0.0;
    for (int k = 0; k < g.samples(x, y); ++k)
        sum += double(channel(g, x, y, k, gbuffer::kSampleWeight)) *
               double(channel(g, x, y, k, gbuffer::kCoverage));
    return sum;
}

} // namespace

TEST(PixelSamples, AnEdgesCoverageIsTheFiltersIntegral) {
    // The edge 0.3 px right of the boundary between pixels 31 and 32: pixel 32's centre is 0.2
    // px beyond it, pixel 31's 0.8 px before it. Mean over the rows against the closed form.
    const EdgeScene s(0.3f);
    for (const PixelFilter f :
         {PixelFilter::Box, PixelFilter::BlackmanHarris, PixelFilter::Gaussian}) {
        SCOPED_TRACE(int(f));
        GBufferParams p;
        p.samples = 16;
        p.pixelFilter = f;
        p.filterWidth = f == PixelFilter::Box ? 1.0f : 1.5f;
        const DeepGBuffer g = deepOf(s.scene, s.camera, p, s.kW, s.kH);
        for (const int x : {30, 31, 32, 33}) {
            double mean = 0.0;
            for (int y = 0; y < s.kH; ++y)
                mean += coverage(g, x, y) / s.kH;
            const double expected = filterCdf(f, p.filterWidth, 0.3 - (x - 32 + 0.5));
            EXPECT_NEAR(mean, expected, 0.02) << "pixel " << x;
        }
        // Away from the edge one ray a pixel: the quad's and the background's.
        EXPECT_EQ(g.samples(10, 5), 1);
        EXPECT_EQ(channel(g, 10, 5, 0, gbuffer::kSampleWeight), 1.0f);
        EXPECT_EQ(g.samples(50, 5), 0);
        // The edge's pixel: some of its 16 rays hit the quad, not all.
        EXPECT_GT(g.samples(32, 5), 0);
        EXPECT_LT(g.samples(32, 5), 16);
    }
}

TEST(PixelSamples, PixelsAwayFromEdgesAreTheOneRayFramesBitForBit) {
    Scene scene = emptyScene();
    addFloor(scene, 3.0f);
    addBox(scene, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f});
    const Camera camera = Camera::lookAt({2, 2.5, 4}, {0, 0.4, 0}, {0, 1, 0}, glm::radians(40.0));
    GBufferParams one, many;
    many.samples = 16;
    const DeepGBuffer a = deepOf(scene, camera, one, 96, 72),
                      b = deepOf(scene, camera, many, 96, 72);
    const int nch = a.spec.nchannels;
    ASSERT_EQ(b.spec.nchannels, nch + 2);
    int refined = 0, same = 0;
    for (int y = 0; y < 72; ++y)
        for (int x = 0; x < 96; ++x) {
            const bool rays = b.samples(x, y) > 0
                                  ? channel(b, x, y, 0, gbuffer::kSampleWeight) < 1.0f
                                  : a.samples(x, y) > 0;
            if (rays) {
                ++refined;
                // 16 rays, each its 1/16.
                std::map<float, float> rays;
                for (int k = 0; k < b.samples(x, y); ++k)
                    rays[channel(b, x, y, k, gbuffer::kSampleId)] =
                        channel(b, x, y, k, gbuffer::kSampleWeight);
                for (const auto& [id, w] : rays)
                    EXPECT_EQ(w, 1.0f / 16.0f);
                continue;
            }
            ASSERT_EQ(b.samples(x, y), a.samples(x, y)) << x << "," << y;
            if (a.samples(x, y) == 0) continue;
            ++same;
            EXPECT_EQ(std::memcmp(a.sample(x, y, 0), b.sample(x, y, 0), sizeof(float) * nch), 0)
                << x << "," << y;
            EXPECT_EQ(channel(b, x, y, 0, gbuffer::kSampleWeight), 1.0f);
            EXPECT_EQ(channel(b, x, y, 0, gbuffer::kSampleId), 0.0f);
        }
    // The box's silhouette and creases, and the floor's edges: a few percent of the pixels.
    EXPECT_GT(refined, 200);
    EXPECT_LT(refined, 96 * 72 / 4);
    EXPECT_GT(same, 96 * 72 / 2);
    // The same bits with one thread or two and strips cut anywhere.
    const DeepGBuffer c = deepOf(scene, camera, many, 96, 72, 1, 37);
    EXPECT_EQ(b.first, c.first);
    EXPECT_TRUE(b.values == c.values);
}

TEST(PixelSamples, TheLitResolveIsTheFlattenOfItsLitSamples) {
    // dhdr-light's pixel of several rays against OpenImageIO's flatten of the samples it lit
    // (stored as C_k / (1 − Σ_{j<k} alpha(C_j))): 1e-5 relative.
    Scene scene = emptyScene();
    addFloor(scene, 3.0f);
    addBox(scene, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f});
    const Camera camera = Camera::lookAt({2, 2.5, 4}, {0, 0.4, 0}, {0, 1, 0}, glm::radians(40.0));
    GBufferParams p;
    p.samples = 16;
    DeepGBuffer g = deepOf(scene, camera, p, 64, 48);
    // The reader's order: front to back by Z.
    std::string error;
    {
        OIIO::DeepData data;
        toDeepData(g, 0, 48, data);
        OIIO::ImageSpec spec = g.spec;
        spec.deep = true;
        spec.channelformats = gbuffer::channelFormats(spec.channelnames);
        const std::string path = ::testing::TempDir() + "/pixel_samples.exr";
        auto out = OIIO::ImageOutput::create(path);
        ASSERT_TRUE(out && out->open(path, spec) && out->write_deep_image(data) && out->close());
        ASSERT_TRUE(readDeepGBuffer(path, 0, g, error)) << error;
    }
    Light light;
    light.type = LightType::Point;
    light.position = {2, 3, 2};
    light.color = glm::vec3(1.0f);
    light.intensity = 20.0f;
    LightingParams lp;
    OIIO::ImageBuf lit;
    std::vector<float> rgba;
    ASSERT_TRUE(shadeGBuffer(lit, g, {{light}, nullptr}, lp, {}, 0, nullptr, &rgba))
        << lit.geterror();
    int several = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            glm::dvec4 over(0.0);
            for (int k = 0; k < g.samples(x, y); ++k) {
                const size_t i = 4 * (size_t(g.first[size_t(y) * 64 + size_t(x)]) + size_t(k));
                const glm::dvec4 c(rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]);
                over += (1.0 - over.a) * c;
            }
            several += g.samples(x, y) > 1;
            const float* out = static_cast<const float*>(lit.pixeladdr(x, y));
            for (int c = 0; c < 4; ++c)
                EXPECT_NEAR(out[c], over[c], 1e-5 * std::max(1.0, std::abs(over[c])))
                    << x << "," << y << " channel " << c;
        }
    EXPECT_GT(several, 50);
}
