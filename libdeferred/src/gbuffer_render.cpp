#include <dhdr/deferred/gbuffer_render.h>

#include <dhdr/deferred/gbuffer.h>
#include <dhdr/deferred/ray_caster.h>
#include <dhdr/deferred/scene.h>

#include <OpenImageIO/imagebufalgo_util.h>

#include <atomic>
#include <cmath>
#include <limits>

namespace dhdr {

namespace {

// Shading attributes of a hit, interpolated over its triangle.
struct SurfaceSample {
    glm::dvec3 position;
    glm::dvec3 normal;
    glm::vec3 albedo;
    const Material* material;
};

SurfaceSample surfaceAt(const Scene& scene, const Ray& ray, const RayHit& hit) {
    const Mesh& mesh = scene.meshes[size_t(hit.mesh)];
    const glm::uvec3 tri = mesh.triangles[size_t(hit.triangle)];
    const double w1 = hit.u, w2 = hit.v, w0 = 1.0 - w1 - w2;
    SurfaceSample s;
    s.position = ray.origin + hit.t * ray.direction;
    s.normal = w0 * glm::dvec3(mesh.normals[tri[0]]) + w1 * glm::dvec3(mesh.normals[tri[1]]) +
               w2 * glm::dvec3(mesh.normals[tri[2]]);
    if (glm::dot(s.normal, s.normal) < 1e-20) {
        const glm::dvec3 a(mesh.positions[tri[0]]), b(mesh.positions[tri[1]]),
            c(mesh.positions[tri[2]]);
        s.normal = glm::cross(b - a, c - a);
    }
    s.normal = glm::normalize(s.normal);
    // The contract's normals face the camera: a back face is shaded as seen.
    if (glm::dot(s.normal, ray.direction) > 0.0) s.normal = -s.normal;

    s.material = &scene.materials[size_t(mesh.material)];
    s.albedo = s.material->baseColor;
    if (s.material->baseColorTexture >= 0 && !mesh.uvs.empty()) {
        const glm::vec2 uv = float(w0) * mesh.uvs[tri[0]] + float(w1) * mesh.uvs[tri[1]] +
                             float(w2) * mesh.uvs[tri[2]];
        s.albedo *= glm::vec3(scene.textures[size_t(s.material->baseColorTexture)].sample(uv));
    }
    return s;
}

void setNameTable(OIIO::ImageSpec& spec, const char* name, const std::vector<std::string>& names) {
    std::vector<const char*> pointers;
    pointers.push_back(""); // id 0: background
    for (const std::string& n : names) pointers.push_back(n.c_str());
    spec.attribute(name, OIIO::TypeDesc(OIIO::TypeDesc::STRING, int(pointers.size())),
                   pointers.data());
}

} // namespace

std::vector<OIIO::TypeDesc> gbufferChannelFormats() {
    std::vector<OIIO::TypeDesc> formats;
    for (const std::string& name : gbuffer::channelNames()) {
        if (name == gbuffer::kDepth || name.rfind("P.", 0) == 0)
            formats.push_back(OIIO::TypeDesc::FLOAT);
        else if (name.rfind("id.", 0) == 0)
            formats.push_back(OIIO::TypeDesc::UINT);
        else
            formats.push_back(OIIO::TypeDesc::HALF);
    }
    return formats;
}

bool renderGBuffer(OIIO::ImageBuf& dst, const Scene& scene, const Camera& camera,
                   const GBufferParams& params, int nthreads) {
    if (params.width <= 0 || params.height <= 0) {
        dst.errorfmt("image size {}x{} is not positive", params.width, params.height);
        return false;
    }
    const RayCaster caster(scene);
    if (!caster.ok()) {
        dst.errorfmt("{}", caster.error());
        return false;
    }
    const std::vector<std::string> names = gbuffer::channelNames();
    OIIO::ImageSpec spec(params.width, params.height, int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.alpha_channel = 0;
    spec.z_channel = 1;
    const double aspect = double(params.width) / double(params.height);
    gbuffer::CameraInfo info;
    info.worldToCamera = camera.worldToCamera();
    info.worldToNDC = camera.worldToNDC(aspect);
    gbuffer::writeCamera(spec, info);
    const glm::dvec3 eye = camera.position();
    const float eyeF[3] = {float(eye.x), float(eye.y), float(eye.z)};
    spec.attribute("dhdr:cameraPosition", OIIO::TypeVector, eyeF);
    spec.attribute("dhdr:yfovDegrees", float(glm::degrees(camera.yfov)));
    std::vector<std::string> materialNames;
    for (const Material& m : scene.materials) materialNames.push_back(m.name);
    setNameTable(spec, "dhdr:objectNames", scene.objectNames);
    setNameTable(spec, "dhdr:materialNames", materialNames);
    dst.reset(spec);

    const glm::dmat4 worldToCamera = info.worldToCamera;
    std::atomic<int> rowsDone{0};
    const OIIO::ROI roi = dst.roi();
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y) {
            for (int x = r.xbegin; x < r.xend; ++x) {
                float* px = static_cast<float*>(dst.pixeladdr(x, y));
                const Ray ray = camera.primaryRay(x, y, params.width, params.height);
                const RayHit hit = caster.intersect(ray);
                if (!hit.hit) {
                    std::fill(px, px + names.size(), 0.0f);
                    px[1] = std::numeric_limits<float>::infinity();
                    continue;
                }
                const SurfaceSample s = surfaceAt(scene, ray, hit);
                const Material& m = *s.material;
                float* out = px;
                *out++ = 1.0f;
                *out++ = float(-(worldToCamera * glm::dvec4(s.position, 1.0)).z);
                for (int c = 0; c < 3; ++c) *out++ = float(s.position[c]);
                for (int c = 0; c < 3; ++c) *out++ = float(s.normal[c]);
                for (int c = 0; c < 3; ++c) *out++ = s.albedo[c];
                *out++ = m.roughness;
                *out++ = m.metallic;
                for (int c = 0; c < 3; ++c) *out++ = m.emission[c];
                *out++ = float(scene.meshes[size_t(hit.mesh)].object + 1);
                *out++ = float(scene.meshes[size_t(hit.mesh)].material + 1);
            }
            const int done = ++rowsDone;
            if (params.progress && (done % 64 == 0 || done == params.height))
                params.progress(float(done) / float(params.height));
        }
    });
    return true;
}

} // namespace dhdr
