#include "direct/direct_lighting.h"
#include "gi/bounce_light.h"
#include "gi/specular_indirect.h"
#include "integrator/filtered_estimates.h"
#include "integrator/path_tracer.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/direct/ambient_occlusion.h>
#include <dhdr/deferred/direct/shadows.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/shading_point.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/lights/environment.h>
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

// What the shading loop reads first for every candidate light, packed by field (structure of
// arrays): enough to skip a light whose range does not reach the pixel without touching the
// rest of it.
struct LightReach {
    std::vector<float> x, y, z, range2;

    explicit LightReach(const std::vector<Light>& lights) {
        for (const Light& l : lights) {
            const bool bounded = l.isLocal() && std::isfinite(l.range);
            x.push_back(l.position.x);
            y.push_back(l.position.y);
            z.push_back(l.position.z);
            range2.push_back(bounded ? l.range * l.range : INFINITY);
        }
    }
    // False when the light's window is zero at P.
    bool reaches(std::uint32_t i, const glm::vec3& P) const {
        const float dx = x[i] - P.x, dy = y[i] - P.y, dz = z[i] - P.z;
        return dx * dx + dy * dy + dz * dz < range2[i];
    }
};

// The angle the mirror directions of flat pixel (x, y) span: across and down, the angle
// between its mirror direction and its neighbour's (the next pixel, else the previous),
// the larger of the two; neighbours of another object or whose normal turns by more than 60°
// are another surface and do not count (0 when none does). Ray cones (Akenine-Möller et al.
// 2019) measure the same spread from the curvature; the G-buffer has the neighbours instead.
float reflectionSpread(const GBufferView& view, const gbuffer::Layout& layout, OIIO::ROI held,
                       int x, int y, const ShadingPoint& sp) {
    const glm::vec3 R = glm::reflect(-sp.V, sp.N);
    const float object = layout.objectId >= 0 ? view.channels(x, y)[layout.objectId] : 0.0f;
    float spread = 0.0f;
    for (const glm::ivec2 axis : {glm::ivec2(1, 0), glm::ivec2(0, 1)})
        for (const int side : {1, -1}) {
            const int qx = x + side * axis.x, qy = y + side * axis.y;
            if (qx < held.xbegin || qx >= held.xend || qy < held.ybegin || qy >= held.yend ||
                view.samples(qx, qy) == 0)
                continue;
            if (layout.objectId >= 0 && view.channels(qx, qy)[layout.objectId] != object) continue;
            const ShadingPoint q = view.at(qx, qy);
            if (!(glm::dot(q.N, sp.N) > 0.5f)) continue;
            const float c = std::clamp(glm::dot(R, glm::reflect(-q.V, q.N)), -1.0f, 1.0f);
            spread = std::max(spread, std::acos(c));
            break;
        }
    return spread;
}

} // namespace

LightingStats& LightingStats::operator+=(const LightingStats& o) {
    lightEvaluations += o.lightEvaluations;
    lightsReaching += o.lightsReaching;
    coveredPixels += o.coveredPixels;
    tileListEntries += o.tileListEntries;
    shadowRays += o.shadowRays;
    aoRays += o.aoRays;
    bounceRays += o.bounceRays;
    pathRays += o.pathRays;
    specularRays += o.specularRays;
    return *this;
}

namespace {

// A G-buffer opened for shading: flat (a strip of a frame, or all of it) or deep.
struct Source {
    const OIIO::ImageSpec& spec; // its header and channels; size and place of its pixels
    OIIO::ROI roi;               // the pixels it holds
    const gbuffer::Layout& layout;
    const gbuffer::CameraInfo& camera;
    GBufferView view;
    DepthView depth;
};

bool shadeSource(OIIO::ImageBuf& dst, const Source& source, const LightingInputs& inputs,
                 const LightingParams& params, OIIO::ROI roi, int nthreads, LightingStats* stats,
                 std::vector<float>* sampleRGBA) {
    const std::vector<Light>& lights = inputs.lights;
    const OIIO::ImageSpec& in = source.spec;
    const gbuffer::Layout& layout = source.layout;
    const gbuffer::CameraInfo& camera = source.camera;
    const GBufferView& view = source.view;
    std::vector<int> passIndex;
    for (const std::string& name : params.passThrough) {
        const int c = in.channelindex(name);
        if (c < 0) {
            dst.errorfmt("no channel '{}' to pass through", name);
            return false;
        }
        passIndex.push_back(c);
    }
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

    // AOVs after RGBA: AO, then the probes' indirect light, then the specular indirect light,
    // then the channels passed through.
    const ProbeVolume* probes = inputs.probes;
    const bool writeIndirect = params.writeIndirect && probes;
    const bool specularActive = inputs.scene && params.specularSamples > 0 && !params.pathTrace;
    const bool writeSpecular = params.writeSpecular && specularActive;
    const int indirectAt = params.writeAO ? 1 : 0;
    const int specularAt = indirectAt + (writeIndirect ? 3 : 0);
    const int extra = specularAt + (writeSpecular ? 3 : 0);
    OIIO::ImageSpec spec = in;
    spec.x = roi.xbegin;
    spec.y = roi.ybegin;
    spec.width = roi.width();
    spec.height = roi.height();
    spec.nchannels = 4 + extra + int(passIndex.size());
    spec.channelnames = {"R", "G", "B", "A"};
    if (params.writeAO) spec.channelnames.push_back("AO");
    if (writeIndirect)
        spec.channelnames.insert(spec.channelnames.end(),
                                 {"indirect.R", "indirect.G", "indirect.B"});
    if (writeSpecular)
        spec.channelnames.insert(spec.channelnames.end(),
                                 {"specular.R", "specular.G", "specular.B"});
    for (const std::string& name : params.passThrough)
        spec.channelnames.push_back(name);
    spec.alpha_channel = 3;
    spec.z_channel = spec.channelindex("Z");
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.channelformats.clear();
    const OIIO::ImageSpec& held = dst.spec();
    if (dst.initialized() && dst.localpixels() && held.format == OIIO::TypeDesc::FLOAT &&
        held.channelformats.empty() && held.nchannels == spec.nchannels &&
        held.width == spec.width && held.height == spec.height) {
        dst.specmod() = spec;
    } else {
        dst.reset(spec, OIIO::InitializePixels::No);
    }

    // The frame the tiles are laid over; the G-buffer may be a strip of its rows.
    const OIIO::ROI frame = params.frame.defined() ? params.frame : source.roi;
    if (in.x != frame.xbegin || in.width != frame.width() || in.y < frame.ybegin ||
        in.y + in.height > frame.yend) {
        dst.errorfmt("the G-buffer is not a strip of whole rows of the frame");
        return false;
    }
    const int frameWidth = frame.width(), frameHeight = frame.height();
    const DepthView& depth = source.depth;
    TileLightLists tiles;
    if (!params.bruteForce)
        tiles.build(lights, camera, depth, frameWidth, frameHeight, params.tileSize, nthreads,
                    roi.ybegin - frame.ybegin, roi.yend - frame.ybegin);
    const LightReach reach(lights);
    const Visibility* shadowRays = params.shadows ? inputs.visibility : nullptr;
    // AO scales ambient lights, probes and environments without shadow rays; where nothing
    // reads it (and no AOV asks for it), its rays are not traced.
    const bool environmentsTraced = shadowRays && params.environmentSamples > 0;
    const bool aoRead =
        params.writeAO || probes || std::any_of(lights.begin(), lights.end(), [&](const Light& l) {
            return l.type == LightType::Ambient ||
                   (l.type == LightType::Environment && !environmentsTraced);
        });
    const bool rayTracedAO = !ao && inputs.visibility && params.aoSamples > 0 && aoRead;
    const bool aoActive = ao || rayTracedAO;
    DirectLightingOptions directOptions;
    directOptions.shadows = shadowRays;
    directOptions.shadowSamples = params.shadowSamples;
    directOptions.environmentSamples = params.environmentSamples;
    // With probes, the environment's diffuse light comes through them (their rays see the sky
    // where nothing blocks it); its specular light stays the IBL's.
    directOptions.environmentDiffuse = !probes;
    directOptions.environmentSpecular = params.environmentSpecular;
    directOptions.occludable = aoActive;
    const DirectLighting direct(lights, directOptions);
    // Environments' and suns' specular light is filtered over each flat pixel's footprint.
    const bool footprint = std::any_of(lights.begin(), lights.end(), [](const Light& l) {
        return (l.type == LightType::Environment && l.ibl) ||
               (l.type == LightType::Directional && l.angle > 0.0f);
    });
    // What secondary rays see (a shadow catcher's bounce light, the specular indirect light):
    // the surfaces they hit lit by every light (each shadowed by one ray; environments
    // unshadowed, their specular light by the split sum) and the probes.
    const float catcherId = float(in.get_int_attribute(gbuffer::kShadowCatcher, 0));
    DirectLightingOptions hitOptions;
    hitOptions.shadows = shadowRays;
    hitOptions.environmentSpecular = IblSpecular::SplitSum;
    // As at the pixels: with probes, environments' diffuse light comes through them.
    hitOptions.environmentDiffuse = !probes;
    const DirectLighting atHits(lights, hitOptions);
    const bool emissionAtHits = std::none_of(
        lights.begin(), lights.end(), [](const Light& l) { return l.type == LightType::Mesh; });
    std::optional<HitShading> hitShading;
    if (inputs.scene && !params.pathTrace)
        hitShading.emplace(*inputs.scene, atHits, probes, emissionAtHits, kHitMinRoughness,
                           params.diffuse);
    std::optional<BounceLighting> bounceLight;
    if (hitShading && shadowRays && catcherId > 0 && params.catcherBounceSamples > 0)
        bounceLight.emplace(*hitShading);
    std::optional<SpecularIndirect> specularLight;
    if (hitShading && specularActive) specularLight.emplace(*hitShading);
    // The reference replaces all of the above at every sample.
    std::optional<PathTracer> tracer;
    if (params.pathTrace)
        tracer.emplace(lights, *inputs.scene,
                       PathTracerOptions{params.pathSamples, params.pathBounces, params.diffuse});
    // Denoised estimates (flat G-buffers): computed for every pixel the source holds (a
    // strip's halo rows included) and filtered before the shading reads them.
    LightingParams estimated = params;
    estimated.denoise = params.denoise && !params.pathTrace;
    const FilteredEstimates filtered(
        view, layout, source.roi, roi, lights, estimated, shadowRays,
        rayTracedAO ? inputs.visibility : nullptr,
        TracedEstimates{bounceLight ? &*bounceLight : nullptr, catcherId,
                        specularLight ? &*specularLight : nullptr, probes != nullptr},
        nthreads, inputs.carry);
    // The environment behind the surfaces: the view ray through each pixel's centre, from the
    // inverse of worldToNDC (the near and far planes' points).
    const Light* sky = nullptr;
    if (params.environmentBackground || params.plateEnvironment)
        for (const Light& l : lights)
            if (l.type == LightType::Environment && l.ibl) {
                sky = &l;
                break;
            }
    const glm::dmat4 ndcToWorld = glm::inverse(camera.worldToNDC);
    auto skyRadiance = [&](int px, int py) {
        const double nx = (px + 0.5) / frameWidth * 2.0 - 1.0;
        const double ny = 1.0 - (py + 0.5) / frameHeight * 2.0;
        const glm::dvec4 a = ndcToWorld * glm::dvec4(nx, ny, -1.0, 1.0);
        const glm::dvec4 b = ndcToWorld * glm::dvec4(nx, ny, 1.0, 1.0);
        const glm::vec3 d(glm::normalize(glm::dvec3(b) / b.w - glm::dvec3(a) / a.w));
        return environmentRadiance(*sky, d);
    };
    // Composited over a plate: a photograph of the frame's pixels, or the environment.
    const OIIO::ImageBuf* plateImage = inputs.plate;
    const bool plate = plateImage || (params.plateEnvironment && sky);
    auto overPlate = [&](float* out, int x, int y) {
        glm::vec3 behind(0.0f);
        if (plateImage) {
            for (int c = 0; c < 3; ++c)
                behind[c] =
                    plateImage->getchannel(x, y, 0, std::min(c, plateImage->nchannels() - 1));
        } else {
            behind = skyRadiance(x - frame.xbegin, y - frame.ybegin);
        }
        const float a = out[3];
        for (int c = 0; c < 3; ++c)
            out[c] += behind[c] * (1.0f - a);
        out[3] = 1.0f;
    };
    // One surface sample lit: RGBA, premultiplied by the sample's alpha in a deep G-buffer (a
    // flat pixel keeps its RGB and its coverage as A); `aovs` receives its AO and indirect
    // light.
    auto shadeSample = [&](int x, int y, int k, LightingStats& local, float* aovs) {
        const ShadingPoint sp = view.at(x, y, k);
        const float* g = view.channels(x, y, k);
        if (tracer) {
            const glm::vec3 Lo =
                sp.emission + tracer->radiance({sp.surface, sp.P, sp.N, sp.V, sp.origin}, x, y, k,
                                               &local.pathRays);
            if (aovs) {
                if (params.writeAO) aovs[0] = 1.0f;
                if (writeIndirect) std::fill(aovs + indirectAt, aovs + indirectAt + 3, 0.0f);
                if (writeSpecular) std::fill(aovs + specularAt, aovs + specularAt + 3, 0.0f);
            }
            return view.deep() ? glm::vec4(Lo * sp.coverage, sp.coverage)
                               : glm::vec4(Lo, sp.coverage);
        }
        float occlusion = 1.0f;
        if (ao)
            occlusion = std::clamp(ao->getchannel(x, y, 0, 0), 0.0f, 1.0f);
        else if (filtered.filtersAO() && k == 0)
            occlusion = filtered.ambientOcclusion(x, y);
        else if (rayTracedAO)
            occlusion = rayTracedOcclusion(
                sp.origin, sp.N, sampleSeed(x, y, -1, streamOf(SampleStream::AmbientOcclusion, k)),
                params.aoSamples, params.aoDistance, *inputs.visibility, &local.aoRays);
        // Lo = Le + Σ V_i L_i, in the order of the lights; with AO, the ambient terms are
        // summed apart and occluded at the end. The same sums without visibility give a
        // shadow catcher its alpha.
        DirectTerms lit{sp.emission}, open{sp.emission};
        LitPoint point{sp.surface,
                       sp.P,
                       sp.N,
                       sp.V,
                       sp.origin,
                       footprint && !view.deep()
                           ? reflectionSpread(view, layout, source.roi, x, y, sp)
                           : 0.0f};
        point.tracedSpecular = specularLight && SpecularIndirect::traced(point, probes);
        point.specularFromProbes =
            probes && !point.tracedSpecular && sp.surface.roughness >= kProbeGlossyRoughness;
        const SeedKey key{x, y, streamOf(SampleStream::Shadow, k)};
        auto addLight = [&](std::uint32_t i) {
            // Sample 0 of a flat pixel reads the denoised environment estimates.
            EnvironmentVisibility v;
            const bool given = filtered.filters(i) && k == 0;
            if (given) v = filtered.visibility(i, x, y);
            direct.add(i, point, key, lit, &open, given ? &v : nullptr, &local.shadowRays);
        };
        if (params.bruteForce) {
            // The reference: every light's full evaluation, which is exactly zero where it
            // does not reach.
            for (std::uint32_t i = 0; i < lights.size(); ++i) {
                local.lightsReaching += reach.reaches(i, sp.P);
                addLight(i);
            }
            local.lightEvaluations += (long long)lights.size();
        } else {
            const int px = x - frame.xbegin, py = y - frame.ybegin;
            const std::uint32_t slice = tiles.sliceBit(px, py, sp.depth);
            for (const TileLightLists::Entry& e : tiles.at(px, py)) {
                if (!(e.depthMask & slice)) continue;
                ++local.lightEvaluations;
                // Out of range, the window is exactly zero: skip before reading more.
                if (!reach.reaches(e.light, sp.P)) continue;
                ++local.lightsReaching;
                addLight(e.light);
            }
        }
        const float so = aoActive ? specularOcclusion(std::max(glm::dot(sp.N, sp.V), 0.0f),
                                                      occlusion, sp.surface.roughness)
                                  : 1.0f;
        const glm::vec3 shaded = lit.total(occlusion, so);
        // Indirect light from the probes: the diffuse layer's (diffuseAlbedo × E / π, as for
        // environments) and, where the probes bring it, the rough specular lobe's
        // (specularAlbedo × E / π, as the bake's hits reflect it); occluded by AO like the
        // ambient terms.
        glm::vec3 indirect(0.0f);
        if (probes) {
            indirect = probes->reflectedAt(sp.surface, sp.P, sp.N, sp.V, point.specularFromProbes,
                                           inputs.visibility);
            if (aoActive) indirect *= occlusion;
        }
        // The scene in the glossy lobe, traced (not occluded by AO: its rays see the occluders).
        glm::vec3 reflected(0.0f);
        if (point.tracedSpecular)
            reflected = filtered.filtersSpecular() && k == 0
                            ? filtered.specularIndirect(x, y)
                            : specularLight->radiance(point, x, y, k, params.specularSamples,
                                                      &local.specularRays);
        const glm::vec3 Lo = shaded + indirect + reflected;
        if (aovs) {
            if (params.writeAO) aovs[0] = occlusion;
            if (writeIndirect)
                for (int c = 0; c < 3; ++c)
                    aovs[indirectAt + c] = indirect[c];
            if (writeSpecular)
                for (int c = 0; c < 3; ++c)
                    aovs[specularAt + c] = reflected[c];
        }
        if (catcherId > 0 && layout.objectId >= 0 && g[layout.objectId] == catcherId) {
            // A shadow catcher (Blender's convention): no colour of its own, and the share of
            // light that shadows and AO take away, less what the objects bounce back onto it
            // (its diffuse reflection of the bounce irradiance), as alpha.
            float bounce = 0.0f;
            if (filtered.filtersBounce() && k == 0)
                bounce = filtered.catcherBounce(x, y);
            else if (bounceLight)
                bounce = luminance(
                    diffuseAlbedo(sp.surface, std::max(glm::dot(sp.N, sp.V), 0.0f)) / kPi *
                    bounceLight->irradianceAt(sp.origin, sp.N, x, y, k, params.catcherBounceSamples,
                                              &local.bounceRays));
            const float unshadowed = luminance(open.total(1.0f, 1.0f));
            return glm::vec4(
                0.0f, 0.0f, 0.0f,
                unshadowed > 0.0f
                    ? std::clamp(1.0f - (luminance(shaded) + bounce) / unshadowed, 0.0f, 1.0f)
                    : 0.0f);
        }
        return view.deep() ? glm::vec4(Lo * sp.coverage, sp.coverage) : glm::vec4(Lo, sp.coverage);
    };
    LightingStats total;
    std::mutex totalMutex;
    parallelImageRows(roi, nthreads, [&](OIIO::ROI r) {
        LightingStats local;
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                float* out = static_cast<float*>(dst.pixeladdr(x, y));
                const int samples = view.samples(x, y);
                for (size_t k = 0; k < passIndex.size(); ++k)
                    out[4 + extra + k] =
                        samples > 0 || !view.deep() ? view.channels(x, y)[passIndex[k]] : 0.0f;
                if (samples == 0) {
                    std::copy(params.background, params.background + 4, out);
                    if (sky && params.environmentBackground) {
                        const glm::vec3 L = skyRadiance(x - frame.xbegin, y - frame.ybegin);
                        out[0] = L.r;
                        out[1] = L.g;
                        out[2] = L.b;
                        out[3] = 1.0f;
                    }
                    if (params.writeAO) out[4] = 1.0f;
                    if (writeIndirect) std::fill(out + 4 + indirectAt, out + 7 + indirectAt, 0.0f);
                    if (writeSpecular) std::fill(out + 4 + specularAt, out + 7 + specularAt, 0.0f);
                    if (plate) overPlate(out, x, y);
                    continue;
                }
                // The samples front to back, each lit like an opaque surface and composited
                // premultiplied "over" the ones before it (a flat pixel: its one sample as is).
                glm::vec4 sum(0.0f);
                for (int k = 0; k < samples; ++k) {
                    const glm::vec4 c =
                        shadeSample(x, y, k, local, k == 0 && extra ? out + 4 : nullptr);
                    if (sampleRGBA)
                        std::copy(&c[0], &c[0] + 4, &(*sampleRGBA)[4 * view.sampleIndex(x, y, k)]);
                    if (!view.deep()) {
                        sum = c;
                        break;
                    }
                    sum += (1.0f - sum.a) * c;
                }
                ++local.coveredPixels;
                out[0] = sum.r;
                out[1] = sum.g;
                out[2] = sum.b;
                out[3] = sum.a;
                if (view.deep() && sum.a < 1.0f && (sky && params.environmentBackground)) {
                    const glm::vec3 L = skyRadiance(x - frame.xbegin, y - frame.ybegin);
                    for (int c = 0; c < 3; ++c)
                        out[c] += (1.0f - sum.a) * L[c];
                    out[3] = 1.0f;
                } else if (view.deep() && sum.a < 1.0f) {
                    for (int c = 0; c < 4; ++c)
                        out[c] += (1.0f - sum.a) * params.background[c];
                }
                if (plate) overPlate(out, x, y);
            }
        const std::lock_guard<std::mutex> lock(totalMutex);
        total += local;
    });
    if (stats) {
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
    const Source source{
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
    const Source source{in,
                        OIIO::get_roi(in),
                        layout,
                        camera,
                        GBufferView(gbuf, layout, camera, params.diffuse),
                        DepthView{gbuf.values.data() + layout.depth, size_t(in.nchannels),
                                  size_t(in.width), in.y - frame.ybegin, gbuf.first.data()}};
    return shadeSource(dst, source, inputs, params, roi, nthreads, stats, sampleRGBA);
}

} // namespace dhdr
