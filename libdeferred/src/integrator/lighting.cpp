#include "integrator/background.h"
#include "integrator/output_plan.h"
#include "integrator/shade_estimators.h"
#include "integrator/shade_sample.h"
#include "integrator/shade_setup.h"
#include "integrator/shade_source.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <atomic>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/lights/light_culling.h>
#include <mutex>
#include <optional>

namespace dhdr {

bool validate(const LightingParams& params, std::string& error) {
    error = checkRanges(params, kLightingParamTable);
    if (error.empty() && !(params.aoDistance > 0.0f))
        error = "--ao-distance: the AO distance must be positive";
    return error.empty();
}

namespace {

// The parameters and inputs checked, and `roi` made the pixels to shade (within the source's);
// false with the error reported on `dst`.
bool checkInputs(OIIO::ImageBuf& dst, const ShadeSource& source, const LightingInputs& inputs,
                 const LightingParams& params, OIIO::ROI& roi) {
    if (std::string error; !validate(params, error)) {
        dst.errorfmt("{}", error);
        return false;
    }
    if (params.pathTrace && !inputs.scene) {
        dst.errorfmt("path tracing needs the scene (LightingInputs::scene)");
        return false;
    }
    roi = roi.defined() ? OIIO::roi_intersection(roi, source.roi) : source.roi;
    if (roi.npixels() == 0) {
        dst.errorfmt("the region to shade is empty");
        return false;
    }
    const OIIO::ImageBuf* ao = inputs.ambientOcclusion;
    if (ao &&
        (ao->nchannels() < 1 ||
         !ao->roi().contains(OIIO::ROI(roi.xbegin, roi.xend, roi.ybegin, roi.yend, 0, 1, 0, 1)))) {
        dst.errorfmt("the AO image does not cover the pixels shaded");
        return false;
    }
    return true;
}

// The stages a pixel goes through, set up for one call.
struct PixelStages {
    const GBufferView& view;
    const OutputPlan& plan;
    const SampleShader& shader;
    const Background& background;
    std::vector<float>* sampleRGBA; // optional: each deep sample's own RGBA
};

// What passes to the samples behind, along one ray: the coverage left (1 − the alpha
// composited so far) and, once a sample that light passes is met, per channel (`through`).
struct Passing {
    float left = 1.0f;
    glm::vec3 through{1.0f};
    bool tinted = false;

    // The factor of sample `c`'s RGB, and what passes on behind it.
    glm::vec3 onto(const ShadedSample& c) {
        const glm::vec3 t = tinted ? through : glm::vec3(left);
        left *= 1.0f - std::clamp(c.rgba.a, 0.0f, 1.0f);
        through = t * glm::clamp(c.behind, 0.0f, 1.0f);
        tinted = tinted || c.passes;
        return t;
    }
    glm::vec3 behind() const { return tinted ? through : glm::vec3(left); }
};

// A pixel of several rays (GBufferView::severalRays): each ray's samples composited "over"
// each other front to back, times the ray's share of the pixel, summed. Each sample's own RGBA
// (`sampleRGBA`) is what makes a front-to-back "over" of all the pixel's samples, in depth order
// (OpenEXR's flatten), give that sum: its contribution C_k over 1 − Σ_{j<k} alpha(C_j).
// `through`: set where light passes some sample, what passes behind all of them per channel.
glm::vec4 resolveRays(const PixelStages& s, float* aovs, int x, int y, LightingStats& local,
                      std::optional<glm::vec3>& through) {
    const GBufferView& view = s.view;
    const int samples = view.samples(x, y);
    // What passes along each ray so far, and the ray's weight; a pixel holds a few dozen rays.
    struct Ray {
        std::uint32_t id;
        float weight;
        Passing passing;
    };
    std::vector<Ray> left;
    glm::vec4 sum(0.0f);
    for (int k = 0; k < samples; ++k) {
        const ShadedSample c = s.shader.shade(x, y, k, local, k == 0 ? aovs : nullptr);
        const std::uint32_t ray = view.ray(x, y, k);
        auto it = std::find_if(left.begin(), left.end(), [&](const Ray& r) { return r.id == ray; });
        if (it == left.end()) it = left.insert(left.end(), {ray, view.rayWeight(x, y, k), {}});
        const float w = it->weight, a = it->passing.left;
        const glm::vec4 contribution(w * it->passing.onto(c) * glm::vec3(c.rgba), w * a * c.rgba.a);
        if (s.sampleRGBA) {
            const float behind = 1.0f - sum.a;
            const glm::vec4 own = behind > 1e-6f ? contribution / behind : glm::vec4(0.0f);
            std::copy(&own[0], &own[0] + 4, &(*s.sampleRGBA)[4 * view.sampleIndex(x, y, k)]);
        }
        sum += contribution;
    }
    sum.a = std::min(sum.a, 1.0f); // a file's weights may add up to more than 1
    // Behind: each ray's share of the pixel passes what passes along it; the rest of the pixel
    // (a ray that missed has no sample) all of it.
    if (std::any_of(left.begin(), left.end(), [](const Ray& r) { return r.passing.tinted; })) {
        glm::vec3 behind(0.0f);
        float weights = 0.0f;
        for (const Ray& r : left) {
            behind += r.weight * r.passing.behind();
            weights += r.weight;
        }
        through = behind + std::max(0.0f, 1.0f - weights);
    }
    return sum;
}

// Pixel (x, y) into `out`: its samples front to back, each lit like an opaque surface and
// composited premultiplied "over" the ones before it (a flat pixel: its one sample as is; a
// pixel of several rays: resolveRays), then what shows behind them.
void shadePixel(const PixelStages& s, float* out, int x, int y, LightingStats& local) {
    const GBufferView& view = s.view;
    const int samples = view.samples(x, y);
    s.plan.passThrough(out, view, x, y, samples);
    if (samples == 0) {
        s.background.uncovered(out, x, y);
        s.plan.writeNone(out + 4);
        if (s.background.plated()) s.background.overPlate(out, x, y);
        return;
    }
    glm::vec4 sum(0.0f);
    std::optional<glm::vec3> through; // set where light passes a sample (transmission)
    if (view.severalRays()) {
        sum = resolveRays(s, s.plan.aovs ? out + 4 : nullptr, x, y, local, through);
    } else {
        // What passes behind the samples so far, per channel, once one tints it; until then
        // 1 − A, as "over" composites.
        glm::vec3 passed(1.0f);
        bool tinted = false;
        for (int k = 0; k < samples; ++k) {
            const ShadedSample c =
                s.shader.shade(x, y, k, local, k == 0 && s.plan.aovs ? out + 4 : nullptr);
            if (!view.deep()) {
                sum = c.rgba;
                if (s.sampleRGBA)
                    std::copy(&sum[0], &sum[0] + 4,
                              &(*s.sampleRGBA)[4 * view.sampleIndex(x, y, 0)]);
                break;
            }
            const glm::vec3 t = tinted ? passed : glm::vec3(1.0f - sum.a);
            const glm::vec4 contribution(t * glm::vec3(c.rgba), (1.0f - sum.a) * c.rgba.a);
            // Its own RGBA: as lit, unless a sample before it tints what passes, when its
            // contribution over what the samples before it leave (resolveRays' form).
            if (s.sampleRGBA) {
                const float behind = 1.0f - sum.a;
                const glm::vec4 own = !tinted          ? c.rgba
                                      : behind > 1e-6f ? contribution / behind
                                                       : glm::vec4(0.0f);
                std::copy(&own[0], &own[0] + 4, &(*s.sampleRGBA)[4 * view.sampleIndex(x, y, k)]);
            }
            sum += contribution;
            passed = t * glm::clamp(c.behind, 0.0f, 1.0f);
            tinted = tinted || c.passes;
        }
        if (tinted) through = passed;
    }
    ++local.coveredPixels;
    out[0] = sum.r;
    out[1] = sum.g;
    out[2] = sum.b;
    out[3] = sum.a;
    if (view.deep() && through)
        s.background.behind(out, sum.a, *through, x, y);
    else if (view.deep() && sum.a < 1.0f)
        s.background.behind(out, sum.a, glm::vec3(1.0f - sum.a), x, y);
    if (s.background.plated()) s.background.overPlate(out, x, y);
}

bool cancelled(const LightingParams& params) {
    return params.cancel && params.cancel->load(std::memory_order_relaxed);
}

// The lighting pass over the pixels of `roi`: the setup, the output plan and the estimators
// once, then every pixel's stages.
bool shadeSource(OIIO::ImageBuf& dst, const ShadeSource& source, const LightingInputs& inputs,
                 const LightingParams& params, OIIO::ROI roi, int nthreads, LightingStats* stats,
                 std::vector<float>* sampleRGBA) {
    const OIIO::ImageSpec& in = source.spec;
    std::vector<int> passIndex;
    if (std::string missing; !findPassThrough(in, params.passThrough, passIndex, missing)) {
        dst.errorfmt("no channel '{}' to pass through", missing);
        return false;
    }
    if (!checkInputs(dst, source, inputs, params, roi)) return false;
    const ShadeSetup setup = setUpShading(inputs, params, in);
    const OutputPlan plan = planOutput(params, setup, std::move(passIndex));
    prepareOutput(dst, plan.spec(in, roi));
    // The frame the tiles are laid over; the G-buffer may be a strip of its rows.
    const OIIO::ROI frame = params.frame.defined() ? params.frame : source.roi;
    if (in.x != frame.xbegin || in.width != frame.width() || in.y < frame.ybegin ||
        in.y + in.height > frame.yend) {
        dst.errorfmt("the G-buffer is not a strip of whole rows of the frame");
        return false;
    }
    TileLightLists tiles;
    if (!params.bruteForce)
        tiles.build(inputs.lights, source.camera, source.depth, frame.width(), frame.height(),
                    params.tileSize, nthreads, roi.ybegin - frame.ybegin, roi.yend - frame.ybegin);
    const ShadeEstimators estimators(source, inputs, params, setup, roi, nthreads);
    const SampleShader shader(source, inputs, params, setup, estimators, plan, tiles, frame);
    const Background background(params, setup, source.camera, frame, inputs.plate);
    const PixelStages stages{source.view, plan, shader, background, sampleRGBA};
    LightingStats total;
    std::mutex totalMutex;
    // Pixels done, for inputs.shaded: a band may take minutes (path tracing at 65536 spp).
    std::atomic<long long> done{0};
    const long long pixels = (long long)roi.width() * (long long)roi.height();
    parallelImageRows(roi, nthreads, [&](OIIO::ROI r) {
        LightingStats local;
        // Polled a pixel at a time: a pixel of the path tracer's most paths takes under a second.
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend && !cancelled(params); ++x) {
                shadePixel(stages, static_cast<float*>(dst.pixeladdr(x, y)), x, y, local);
                if (inputs.shaded) (*inputs.shaded)(++done, pixels);
            }
        const std::lock_guard<std::mutex> lock(totalMutex);
        total += local;
    });
    if (cancelled(params)) {
        dst.errorfmt("cancelled");
        return false;
    }
    if (stats) {
        const FilteredEstimates& filtered = *estimators.filtered;
        *stats = total;
        stats->tileListEntries = (long long)tiles.totalEntries();
        stats->shadowRays += filtered.shadowRayCount;
        stats->aoRays += filtered.aoRayCount;
        stats->bounceRays += filtered.bounceRayCount;
        stats->specularRays += filtered.specularRayCount;
    }
    return true;
}

} // namespace

bool shadeGBuffer(OIIO::ImageBuf& dst, const OIIO::ImageBuf& gbuf, const LightingInputs& inputs,
                  const LightingParams& params, OIIO::ROI roi, int nthreads, LightingStats* stats) {
    GBufferPixels g;
    if (!openGBuffer(gbuf, g, dst)) return false;
    const OIIO::ImageSpec& in = gbuf.spec();
    const OIIO::ROI frame = params.frame.defined() ? params.frame : gbuf.roi();
    const size_t nch = size_t(g.pixels->nchannels());
    const ShadeSource source{
        in,
        gbuf.roi(),
        g.layout,
        g.camera,
        GBufferView(*g.pixels, g.layout, g.camera, params.diffuse),
        DepthView{static_cast<const float*>(g.pixels->localpixels()) + g.layout.depth, nch,
                  nch * size_t(in.width), in.y - frame.ybegin}};
    return shadeSource(dst, source, inputs, params, roi, nthreads, stats, nullptr);
}

bool shadeGBuffer(OIIO::ImageBuf& dst, const DeepGBuffer& gbuf, const LightingInputs& inputs,
                  const LightingParams& params, OIIO::ROI roi, int nthreads, LightingStats* stats,
                  std::vector<float>* sampleRGBA) {
    const OIIO::ImageSpec& in = gbuf.spec;
    gbuffer::Layout layout;
    gbuffer::CameraInfo camera;
    std::string message;
    if (!gbuffer::findLayout(in, layout, message)) {
        dst.errorfmt("no channel '{}' — is this a G-buffer?", message);
        return false;
    }
    if (!gbuffer::readCamera(in, camera, message)) {
        dst.errorfmt("{}", message);
        return false;
    }
    if (gbuf.first.size() != size_t(in.width) * size_t(in.height) + 1 ||
        gbuf.values.size() != gbuf.totalSamples() * size_t(in.nchannels)) {
        dst.errorfmt("the deep G-buffer's sample tables do not match its size");
        return false;
    }
    if (inputs.ambientOcclusion) {
        dst.errorfmt("an AO image has one value a pixel; a deep G-buffer needs ray-traced AO");
        return false;
    }
    // A band of the frame's rows is shaded as the flat strips are (params.frame).
    const OIIO::ROI frame = params.frame.defined() ? params.frame : OIIO::get_roi(in);
    if (sampleRGBA) sampleRGBA->assign(4 * gbuf.totalSamples(), 0.0f);
    const ShadeSource source{in,
                             OIIO::get_roi(in),
                             layout,
                             camera,
                             GBufferView(gbuf, layout, camera, params.diffuse),
                             DepthView{gbuf.values.data() + layout.depth, size_t(in.nchannels),
                                       size_t(in.width), in.y - frame.ybegin, gbuf.first.data()}};
    return shadeSource(dst, source, inputs, params, roi, nthreads, stats, sampleRGBA);
}

} // namespace dhdr
