#include "render/motion_vectors.h"
#include "render/pixel_samples.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/geometry/surface.h>
#include <dhdr/deferred/geometry/uv_footprint.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_info.h>
#include <limits>
#include <optional>

namespace dhdr {

// The Cryptomatte ids of the scene's objects and materials, by index.
struct CryptoIds {
    std::vector<float> objects, materials;
};

namespace {

void setNameTable(OIIO::ImageSpec& spec, const char* name, const std::vector<std::string>& names) {
    std::vector<const char*> pointers;
    pointers.push_back(""); // id 0: background
    for (const std::string& n : names)
        pointers.push_back(n.c_str());
    spec.attribute(name, OIIO::TypeDesc(OIIO::TypeDesc::STRING, int(pointers.size())),
                   pointers.data());
}

// A surface along a primary ray, its alpha, whether light passes it (a transmissive
// material's: KHR_materials_transmission) and whether the ray enters the material's volume
// there (it meets the surface's front).
struct Layer {
    RayHit hit;
    float alpha = 1.0f;
    bool passes = false, entering = false;
};

// Whether light passes the surfaces of `mesh` (a transmission factor over 0; a texel of 0 in
// its texture makes one opaque, which the lighting pass composites alike).
bool transmissive(const Scene& scene, int mesh) {
    return mesh != kGroundPlaneHit &&
           scene.materials[size_t(scene.meshes[size_t(mesh)].material)].transmission > 0.0f;
}

// KHR_materials_volume's absorption behind layer k of the n along `ray`: where the ray enters
// an absorbing medium, Beer's law over the distance to the next layer (the medium's far side,
// or what lies inside it), or over the material's thickness when nothing follows; 1 elsewhere.
glm::vec3 attenuationBehind(const Scene& scene, const Ray& ray, const Layer* layers, int k, int n) {
    const Layer& l = layers[k];
    if (!l.entering) return glm::vec3(1.0f);
    const Material& m = scene.materials[size_t(scene.meshes[size_t(l.hit.mesh)].material)];
    if (!m.absorbs()) return glm::vec3(1.0f);
    const double d = k + 1 < n ? (layers[k + 1].hit.t - l.hit.t) * glm::length(ray.direction)
                               : double(m.thickness);
    return glm::pow(m.attenuationColor, glm::vec3(float(d) / m.attenuationDistance));
}

// The surfaces along `ray` front to back up to and including the first opaque one (with
// `firstOnly`, the first surface of any kind): Mask cut-outs are no surface; Blend surfaces
// are kept while there is room for them and the opaque one (at most maxLayers in all), later
// ones are passed through. The search goes on past a surface from a new origin just beyond
// it, offset along its geometric normal by its position's error bound (offsetRayOrigin), so
// that no kernel's ulps find the same surface again, whatever the distance; hits keep their
// distance along the first ray.
int traceLayers(const Scene& scene, const RayCaster& caster, const Ray& ray, int maxLayers,
                Layer* out, bool firstOnly = false) {
    int n = 0;
    Ray search = ray;
    double travelled = 0.0; // from ray.origin to search.origin, along the direction
    // Bounded: a ray crosses a finite number of surfaces, but rounding must not loop forever.
    for (int step = 0; step < 4096; ++step) {
        RayHit hit = caster.intersect(search);
        if (!hit.hit) break;
        hit.t += travelled;
        const SurfaceSample s = surfaceGeometryAt(scene, ray, hit);
        const SurfacePoint at{glm::vec3(s.position), glm::vec3(s.geometric),
                              float(s.positionError)};
        search.origin = glm::dvec3(offsetRayOrigin(at, glm::vec3(ray.direction)));
        travelled = std::max(travelled, glm::dot(search.origin - ray.origin, ray.direction));
        SurfaceCoverage c;
        if (hit.mesh != kGroundPlaneHit)
            c = surfaceCoverage(scene, hit.mesh, hit.triangle, hit.u, hit.v);
        if (!c.present) continue;
        const bool passes = transmissive(scene, hit.mesh);
        const bool opaque = (c.alpha >= 1.0f && !passes) || firstOnly;
        if (opaque || n < maxLayers - 1) out[n++] = {hit, c.alpha, passes, passes && !s.backFace};
        if (opaque) break;
    }
    return n;
}

// Where a sample's primary ray came from: the camera and the image position (px, py) of a
// width × height image, whose rays `step` pixels across and down give the ray's footprint in
// the textures (a pixel's centre: step 1; one of n × n rays: 1 / n, at least ⅛, as pbrt-v4
// scales its differentials).
struct PixelOf {
    const Camera& camera;
    double px, py;
    int width, height;
    double step = 1.0;
};

bool textured(const Material& m) {
    return !materialTextures(m).empty();
}

// The contract's channels of a hit, where `layout` places them (a flat or a deep sample); its
// textures filtered over the pixel's footprint as `filter` says.
void fillSample(const Scene& scene, const glm::dmat4& worldToCamera, const gbuffer::Layout& layout,
                const CryptoIds& crypto, const Ray& ray, const PixelOf& pixel, TextureFilter filter,
                const RayHit& hit, float alpha, float* out) {
    UvFootprint footprint;
    const bool filtered =
        filter != TextureFilter::Bilinear && hit.mesh != kGroundPlaneHit &&
        textured(scene.materials[size_t(scene.meshes[size_t(hit.mesh)].material)]);
    if (filtered) {
        const PixelOf& p = pixel;
        footprint = uvFootprint(
            scene, hit, ray, p.camera.rayThrough(p.px + p.step, p.py, p.width, p.height),
            p.camera.rayThrough(p.px, p.py + p.step, p.width, p.height), filter);
    }
    const SurfaceSample s = surfaceAt(scene, ray, hit, filtered ? &footprint : nullptr);
    const bool ground = hit.mesh == kGroundPlaneHit;
    const int object = ground ? scene.groundObject : scene.meshes[size_t(hit.mesh)].object;
    const int material = ground ? scene.groundMaterial : scene.meshes[size_t(hit.mesh)].material;
    out[layout.coverage] = alpha;
    out[layout.depth] = float(-(worldToCamera * glm::dvec4(s.position, 1.0)).z);
    if (layout.depthBack >= 0) out[layout.depthBack] = out[layout.depth]; // a point sample
    for (int c = 0; c < 3; ++c) {
        out[layout.position + c] = float(s.position[c]);
        out[layout.normal + c] = float(s.normal[c]);
        out[layout.geometricNormal + c] = float(s.geometric[c]);
        out[layout.albedo + c] = s.albedo[c];
        out[layout.emission + c] = s.emission[c];
    }
    out[layout.positionError] = float(s.positionError) * (1.0f + 0x1p-20f); // rounded up
    if (layout.lift >= 0)
        for (int c = 0; c < 3; ++c)
            out[layout.lift + c] = float(s.lift[c]);
    out[layout.roughness] = s.roughness;
    out[layout.metallic] = s.metallic;
    if (layout.occlusion >= 0) out[layout.occlusion] = s.occlusion;
    if (layout.specular >= 0) {
        for (int c = 0; c < 3; ++c)
            out[layout.specular + c] = s.dielectricF0[c];
        out[layout.specularWeight] = s.dielectricF90;
    }
    if (layout.clearcoat >= 0) {
        out[layout.clearcoat] = s.clearcoat;
        out[layout.clearcoatRoughness] = s.clearcoatRoughness;
        for (int c = 0; c < 3; ++c)
            out[layout.clearcoatNormal + c] = float(s.clearcoatNormal[c]);
    }
    if (layout.sheen >= 0) {
        for (int c = 0; c < 3; ++c)
            out[layout.sheen + c] = s.sheenColor[c];
        out[layout.sheenRoughness] = s.sheenRoughness;
    }
    if (layout.transmission >= 0) out[layout.transmission] = s.transmission;
    // The volume's absorption needs the ray's next layer: set by the deep pass (attenuationBehind).
    if (layout.attenuation >= 0) std::fill_n(out + layout.attenuation, 3, 1.0f);
    out[layout.objectId] = float(object + 1);
    out[layout.materialId] = float(material + 1);
    // Cryptomatte: rank 0 is this surface, covering what its alpha covers; rank 1 is empty
    // (one surface a sample).
    const float ranks[2][4] = {{crypto.objects[size_t(object)], alpha, 0.0f, 0.0f},
                               {crypto.materials[size_t(material)], alpha, 0.0f, 0.0f}};
    for (int c = 0; c < 4; ++c) {
        out[layout.cryptoObject + c] = ranks[0][c];
        out[layout.cryptoMaterial + c] = ranks[1][c];
    }
}

// Whether a triangle of `mesh` has vertex normals that differ: its surface is curved, and
// shadow rays start from a lifted point (Plift).
bool smoothShaded(const Mesh& mesh) {
    for (const glm::uvec3& t : mesh.triangles)
        if (mesh.normals[t[0]] != mesh.normals[t[1]] || mesh.normals[t[1]] != mesh.normals[t[2]])
            return true;
    return false;
}

// The WhenUsed channels the scene's materials (and meshes) ask for.
unsigned channelUses(const Scene& scene) {
    unsigned uses = 0;
    for (const Mesh& mesh : scene.meshes)
        if (smoothShaded(mesh)) {
            uses |= gbuffer::kUsesSmoothNormals;
            break;
        }
    for (const Material& m : scene.materials) {
        if (m.occlusionTexture.texture >= 0) uses |= gbuffer::kUsesOcclusion;
        if (m.dielectricSet) uses |= gbuffer::kUsesSpecular;
        if (m.clearcoat > 0.0f) uses |= gbuffer::kUsesClearcoat;
        if (m.sheen()) uses |= gbuffer::kUsesSheen;
        if (m.transmission > 0.0f) uses |= gbuffer::kUsesTransmission;
        if (m.absorbs()) uses |= gbuffer::kUsesVolume;
    }
    return uses;
}

// Where the writers put each channel: the contract's table, flat or deep.
gbuffer::Layout layoutOf(const std::vector<std::string>& names) {
    OIIO::ImageSpec spec(1, 1, int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    gbuffer::Layout layout;
    std::string missing;
    gbuffer::findLayout(spec, layout, missing);
    return layout;
}

} // namespace

GBufferRenderer::GBufferRenderer(const Scene& scene, const Camera& camera,
                                 const GBufferParams& params)
    : GBufferRenderer(scene, camera, params, std::make_shared<RayCaster>(scene)) {}

GBufferRenderer::GBufferRenderer(const Scene& scene, const Camera& camera,
                                 const GBufferParams& params,
                                 std::shared_ptr<const RayCaster> caster)
    : m_scene(scene), m_camera(camera), m_params(params),
      m_uses(channelUses(scene) | (params.samples > 1 ? gbuffer::kUsesPixelSamples : 0u)),
      m_caster(std::move(caster)) {
    std::vector<std::string> names = gbuffer::channelNames(m_uses);
    if (params.motion)
        names.insert(names.end(), std::begin(gbuffer::kMotion), std::end(gbuffer::kMotion));
    m_spec = OIIO::ImageSpec(std::max(params.width, 1), std::max(params.height, 1),
                             int(names.size()), OIIO::TypeDesc::FLOAT);
    m_spec.channelnames = names;
    m_spec.alpha_channel = 0;
    m_spec.z_channel = 1;
    const double aspect = double(m_spec.width) / double(m_spec.height);
    gbuffer::CameraInfo info;
    info.worldToCamera = camera.worldToCamera();
    info.worldToNDC = camera.worldToNDC(aspect);
    gbuffer::writeCamera(m_spec, info);
    const glm::dvec3 eye = camera.position();
    const float eyeF[3] = {float(eye.x), float(eye.y), float(eye.z)};
    m_spec.attribute("dhdr:cameraPosition", OIIO::TypeVector, eyeF);
    m_spec.attribute("dhdr:projection", camera.orthographic ? "orthographic" : "perspective");
    if (camera.orthographic)
        m_spec.attribute("dhdr:orthographicHeight", float(2.0 * camera.ymag));
    else
        m_spec.attribute("dhdr:yfovDegrees", float(glm::degrees(camera.yfov)));
    std::vector<std::string> materialNames;
    for (const Material& m : scene.materials)
        materialNames.push_back(m.name);
    setNameTable(m_spec, "dhdr:objectNames", scene.objectNames);
    setNameTable(m_spec, "dhdr:materialNames", materialNames);
    auto crypto = std::make_shared<CryptoIds>();
    for (const std::string& name : scene.objectNames)
        crypto->objects.push_back(gbuffer::cryptomatteId(name));
    for (const std::string& name : materialNames)
        crypto->materials.push_back(gbuffer::cryptomatteId(name));
    m_crypto = crypto;
    gbuffer::writeCryptomatteHeader(m_spec, "CryptoObject", scene.objectNames);
    gbuffer::writeCryptomatteHeader(m_spec, "CryptoMaterial", materialNames);
    if (scene.hasGroundPlane) {
        m_spec.attribute(gbuffer::kGroundPlaneY, scene.groundPlaneY);
        m_spec.attribute(gbuffer::kShadowCatcher, scene.groundObject + 1);
    }
}

GBufferRenderer::~GBufferRenderer() = default;

bool GBufferRenderer::ok() const {
    return m_caster->ok();
}
const std::string& GBufferRenderer::error() const {
    return m_caster->error();
}

bool GBufferRenderer::render(OIIO::ImageBuf& dst, OIIO::ROI roi, int nthreads) const {
    if (m_params.width <= 0 || m_params.height <= 0) {
        dst.errorfmt("image size {}x{} is not positive", m_params.width, m_params.height);
        return false;
    }
    if (!ok()) {
        dst.errorfmt("{}", error());
        return false;
    }
    const OIIO::ROI frame = OIIO::get_roi_full(m_spec);
    roi = roi.defined() ? OIIO::roi_intersection(roi, frame) : frame;
    const bool reusable = dst.initialized() && dst.spec().format == OIIO::TypeDesc::FLOAT &&
                          dst.localpixels() && dst.nchannels() == m_spec.nchannels &&
                          dst.spec().width == roi.width() && dst.spec().height == roi.height();
    if (reusable) {
        // The next strip of a frame: same memory, moved to the strip's place.
        dst.set_origin(roi.xbegin, roi.ybegin);
    } else {
        OIIO::ImageSpec spec = m_spec;
        spec.x = roi.xbegin;
        spec.y = roi.ybegin;
        spec.width = roi.width();
        spec.height = roi.height();
        dst.reset(spec);
    }
    roi.chbegin = 0;
    roi.chend = m_spec.nchannels;

    const int nch = m_spec.nchannels;
    const glm::dmat4 worldToCamera = m_camera.worldToCamera();
    const gbuffer::Layout layout = layoutOf(m_spec.channelnames);
    // The motion layer, when there is one, is the last four channels.
    std::optional<MotionVectors> motion;
    if (m_params.motion)
        motion.emplace(m_scene, *m_params.motion, m_camera, m_params.width, m_params.height);
    std::atomic<int> rowsDone{0};
    parallelImageRows(roi, nthreads, [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend && !cancelled(); ++y) {
            for (int x = r.xbegin; x < r.xend; ++x) {
                float* px = static_cast<float*>(dst.pixeladdr(x, y));
                const Ray ray = m_camera.primaryRay(x, y, m_params.width, m_params.height);
                const PixelOf pixel{m_camera, x + 0.5, y + 0.5, m_params.width, m_params.height};
                Layer front;
                if (traceLayers(m_scene, *m_caster, ray, 1, &front, true) == 0) {
                    std::fill(px, px + nch, 0.0f);
                    px[1] = std::numeric_limits<float>::infinity();
                    if (motion) motion->at(ray, RayHit{}, px + nch - 4);
                    continue;
                }
                fillSample(m_scene, worldToCamera, layout, *m_crypto, ray, pixel,
                           m_params.textureFilter, front.hit, 1.0f, px);
                if (motion) motion->at(ray, front.hit, px + nch - 4);
            }
            const int done = ++rowsDone;
            if (m_params.progress && (done % 64 == 0 || done == roi.height()))
                m_params.progress(float(done) / float(roi.height()));
        }
    });
    if (cancelled()) {
        dst.errorfmt("interrupted");
        return false;
    }
    return true;
}

std::vector<std::string> GBufferRenderer::deepChannelNames() const {
    std::vector<std::string> names = gbuffer::deepChannelNames(m_uses);
    if (m_params.motion)
        names.insert(names.end(), std::begin(gbuffer::kMotion), std::end(gbuffer::kMotion));
    return names;
}

bool GBufferRenderer::renderDeep(DeepGBuffer& dst, OIIO::ROI roi, int nthreads,
                                 long long* deepSamples) const {
    if (!ok()) return false;
    if (m_params.maxLayers < 1) return false;
    const OIIO::ROI frame = OIIO::get_roi_full(m_spec);
    roi = roi.defined() ? OIIO::roi_intersection(roi, frame) : frame;
    dst.spec = m_spec;
    const std::vector<std::string> names = deepChannelNames();
    dst.spec.nchannels = int(names.size());
    dst.spec.channelnames = names;
    dst.spec.x = roi.xbegin;
    dst.spec.y = roi.ybegin;
    dst.spec.width = roi.width();
    dst.spec.height = roi.height();
    const size_t nch = names.size();
    const glm::dmat4 worldToCamera = m_camera.worldToCamera();
    const gbuffer::Layout layout = layoutOf(names);
    // Every sample carries its own motion (the last four channels).
    std::optional<MotionVectors> motion;
    if (m_params.motion)
        motion.emplace(m_scene, *m_params.motion, m_camera, m_params.width, m_params.height);
    // Each row's samples apart, joined in row order after: the same buffer for any threads.
    std::vector<std::vector<std::uint32_t>> counts(size_t(roi.height()));
    std::vector<std::vector<float>> values(size_t(roi.height()));
    std::atomic<long long> deepOnly{0};
    std::atomic<int> rowsDone{0};
    const int W = m_params.width, H = m_params.height;
    const int grid = int(std::lround(std::sqrt(double(m_params.samples))));
    const bool several = m_params.samples > 1;
    std::optional<PixelFilterSampler> filter;
    std::vector<std::uint8_t> refine;
    if (several) {
        filter.emplace(m_params.pixelFilter, m_params.filterWidth);
        if (!m_params.allPixels) refine = refinedPixels(roi, nthreads);
    }
    parallelImageRows(roi, nthreads, [&](OIIO::ROI r) {
        std::vector<Layer> layers(size_t(m_params.maxLayers));
        long long local = 0;
        // The surfaces along `ray`, ray `id` of its pixel with `weight` of it: their samples.
        // Counted as deep-only: partly transparent samples, and all of a pixel of several rays.
        auto trace = [&](const Ray& ray, const PixelOf& pixel, int id, float weight, bool ofSeveral,
                         std::vector<float>& rowValues) {
            const int n = traceLayers(m_scene, *m_caster, ray, m_params.maxLayers, layers.data());
            for (int k = 0; k < n; ++k) {
                rowValues.resize(rowValues.size() + nch);
                float* out = &rowValues[rowValues.size() - nch];
                fillSample(m_scene, worldToCamera, layout, *m_crypto, ray, pixel,
                           m_params.textureFilter, layers[size_t(k)].hit, layers[size_t(k)].alpha,
                           out);
                if (layout.attenuation >= 0) {
                    const glm::vec3 a = attenuationBehind(m_scene, ray, layers.data(), k, n);
                    for (int c = 0; c < 3; ++c)
                        out[layout.attenuation + c] = a[c];
                }
                if (layout.sampleId >= 0) {
                    out[layout.sampleId] = float(id);
                    out[layout.sampleWeight] = weight;
                }
                if (motion) motion->at(ray, layers[size_t(k)].hit, out + nch - 4);
                local += ofSeveral || layers[size_t(k)].alpha < 1.0f || layers[size_t(k)].passes;
            }
            return n;
        };
        for (int y = r.ybegin; y < r.yend && !cancelled(); ++y) {
            std::vector<std::uint32_t>& rowCounts = counts[size_t(y - roi.ybegin)];
            std::vector<float>& rowValues = values[size_t(y - roi.ybegin)];
            for (int x = r.xbegin; x < r.xend; ++x) {
                const bool rays =
                    several &&
                    (m_params.allPixels ||
                     refine[size_t(y - roi.ybegin) * size_t(W) + size_t(x - roi.xbegin)]);
                int n = 0;
                if (!rays) {
                    n = trace(m_camera.primaryRay(x, y, W, H),
                              PixelOf{m_camera, x + 0.5, y + 0.5, W, H}, 0, 1.0f, false, rowValues);
                } else {
                    const double step = std::max(0.125, 1.0 / grid);
                    for (int k = 0; k < m_params.samples; ++k) {
                        const glm::vec2 o = filter->rayOffset(x, y, k, grid);
                        const double px = x + 0.5 + double(o.x), py = y + 0.5 + double(o.y);
                        n += trace(m_camera.rayThrough(px, py, W, H),
                                   PixelOf{m_camera, px, py, W, H, step}, k,
                                   1.0f / float(m_params.samples), true, rowValues);
                    }
                }
                rowCounts.push_back(std::uint32_t(n));
            }
            const int done = ++rowsDone;
            if (m_params.progress && (done % 64 == 0 || done == roi.height()))
                m_params.progress(float(done) / float(roi.height()));
        }
        deepOnly += local;
    });
    if (cancelled()) return false;
    dst.first.assign(1, 0);
    dst.values.clear();
    for (size_t row = 0; row < counts.size(); ++row) {
        for (const std::uint32_t n : counts[row])
            dst.first.push_back(dst.first.back() + n);
        dst.values.insert(dst.values.end(), values[row].begin(), values[row].end());
    }
    if (deepSamples) *deepSamples = deepOnly;
    return true;
}

std::vector<std::uint8_t> GBufferRenderer::refinedPixels(OIIO::ROI rows, int nthreads) const {
    const int W = m_params.width, H = m_params.height;
    return pixelsToRefine(
        rows, W, H,
        [&](double px, double py) {
            ProbeHit probe;
            const Ray ray = m_camera.rayThrough(px, py, W, H);
            Layer front;
            if (traceLayers(m_scene, *m_caster, ray, 1, &front, true) == 0) return probe;
            const RayHit& hit = front.hit;
            const SurfaceSample s = surfaceGeometryAt(m_scene, ray, hit);
            const bool ground = hit.mesh == kGroundPlaneHit;
            probe.hit = true;
            probe.object = ground ? m_scene.groundObject : m_scene.meshes[size_t(hit.mesh)].object;
            probe.material =
                ground ? m_scene.groundMaterial : m_scene.meshes[size_t(hit.mesh)].material;
            probe.position = s.position;
            probe.normal = glm::dvec3(s.geometric);
            return probe;
        },
        nthreads);
}

std::string samplesError(int samples) {
    const int n = int(std::lround(std::sqrt(double(samples))));
    if (n * n == samples) return {};
    return "--pixel-samples " + std::to_string(samples) +
           ": the rays of a pixel are an n x n grid of strata; give a square (1, 4, 9, 16, 25, "
           "36, 49 or 64)";
}

bool renderGBuffer(OIIO::ImageBuf& dst, const Scene& scene, const Camera& camera,
                   const GBufferParams& params, int nthreads) {
    const GBufferRenderer renderer(scene, camera, params);
    return renderer.render(dst, {}, nthreads);
}

} // namespace dhdr
