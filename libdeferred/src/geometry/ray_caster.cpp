#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <dhdr/deferred/core/cpu_features.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <embree3/rtcore.h>
#include <glm/glm.hpp>
#include <limits>

namespace dhdr {

struct RayCaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    const Scene* source = nullptr;
    bool transparent = false; // some mesh's material masks or blends
    // Some mesh is an instance. Embree 3.13's coherent packet traversal then never returns
    // for some wide cones of rays traced from two threads (a sun of angle 90° over an
    // animated scene, issue 48): such packets are traced as incoherent ones.
    bool instances = false;
    size_t meshes = 0; // the scene's; top-scene geometry IDs from here are stand-ins
    // Per mesh, its world-space vertex buffer, for updateMeshes: its geometry's, or for an
    // instanced mesh its stand-in's.
    std::vector<float*> vertices;
    // Per mesh, the scene an instance of it holds: meshes that move as a whole (Mesh::instance)
    // are traced in their node's space and moved by their instance's transform; null for the
    // others, whose triangles the top scene holds in world space.
    std::vector<RTCScene> instanced;
    // The triangles' bounds, widened by far more than any kernel's rounding: a ray whose
    // segment misses them hits nothing, so it is answered without a call into Embree (most of
    // a shadow catcher's rays and of its sky's shadow rays). The same answers, sooner.
    double lower[3] = {0.0, 0.0, 0.0}, upper[3] = {-1.0, -1.0, -1.0};

    void takeBounds() {
        RTCBounds b;
        rtcGetSceneBounds(scene, &b);
        const double lo[3] = {b.lower_x, b.lower_y, b.lower_z},
                     hi[3] = {b.upper_x, b.upper_y, b.upper_z};
        double size = 0.0;
        for (int c = 0; c < 3; ++c)
            size = std::max({size, hi[c] - lo[c], std::abs(lo[c]), std::abs(hi[c])});
        // An empty scene's bounds are empty (lower > upper): every ray misses.
        const double margin = std::isfinite(size) ? size * 0x1p-12 + 1e-30 : INFINITY;
        for (int c = 0; c < 3; ++c) {
            lower[c] = lo[c] - margin;
            upper[c] = hi[c] + margin;
        }
    }

    // Whether the segment (max(tnear, 0), tfar) of the ray may meet the bounds (slab test in
    // double; a NaN lets the ray through to Embree, as before).
    bool mayHit(const float o[3], const float d[3], float tnear, float tfar) const {
        const double origin[3] = {o[0], o[1], o[2]}, direction[3] = {d[0], d[1], d[2]};
        return meets(origin, direction, std::max(0.0, double(tnear)), double(tfar), 0.0);
    }

    // Whether the segment (t0, t1) of the line o + t d meets the bounds grown by `grow`.
    bool meets(const double o[3], const double d[3], double t0, double t1, double grow) const {
        for (int c = 0; c < 3; ++c) {
            const double lo = lower[c] - grow, hi = upper[c] + grow;
            if (d[c] == 0.0) {
                if (o[c] < lo || o[c] > hi) return false;
                continue;
            }
            const double inverse = 1.0 / d[c];
            double a = (lo - o[c]) * inverse, b = (hi - o[c]) * inverse;
            if (a > b) std::swap(a, b);
            if (a > t0) t0 = a;
            if (b < t1) t1 = b;
            if (t0 > t1) return false;
        }
        return true;
    }

    // Moves instanced mesh `i` to where `mesh` (its Mesh::instance and positions) is now. A
    // transform that float cannot hold or invert (a node scaled to 0 along an axis, or past
    // float's range) cannot move an instance: the mesh's world-space stand-in (geometry ID
    // meshes + i), its vertices refitted, is traced in its place meanwhile.
    void place(unsigned i, const Mesh& mesh) {
        RTCGeometry placed = rtcGetGeometry(scene, i);
        RTCGeometry standIn = rtcGetGeometry(scene, unsigned(meshes) + i);
        float m[16];
        bool usable = true;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) {
                m[4 * c + r] = float((*mesh.instance)[c][r]);
                usable = usable && std::isfinite(m[4 * c + r]);
            }
        // Embree inverts the float matrix in float: its determinant must not vanish there.
        const glm::mat3 linear(glm::vec3(m[0], m[1], m[2]), glm::vec3(m[4], m[5], m[6]),
                               glm::vec3(m[8], m[9], m[10]));
        const glm::mat3 inverse = glm::inverse(linear);
        usable = usable && std::isnormal(glm::determinant(linear));
        for (int c = 0; c < 3; ++c)
            usable = usable && std::isfinite(inverse[c].x + inverse[c].y + inverse[c].z);
        if (usable) {
            rtcSetGeometryTransform(placed, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, m);
            rtcCommitGeometry(placed);
            rtcEnableGeometry(placed);
            rtcDisableGeometry(standIn);
            return;
        }
        float* buffer = vertices[i];
        for (size_t v = 0; v < mesh.positions.size(); ++v)
            for (int c = 0; c < 3; ++c)
                buffer[3 * v + size_t(c)] = mesh.positions[v][c];
        rtcUpdateGeometryBuffer(standIn, RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(standIn);
        rtcEnableGeometry(standIn);
        rtcDisableGeometry(placed);
    }

    ~Impl() {
        for (RTCScene s : instanced)
            if (s) rtcReleaseScene(s);
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {

// The scene's mesh of a hit on top-scene geometry `geom` (in the instance `inst`, or none).
int meshOf(unsigned inst, unsigned geom, size_t meshes) {
    if (inst != RTC_INVALID_GEOMETRY_ID) return int(inst);
    return int(geom >= meshes ? geom - meshes : geom);
}

// What an occlusion query carries through Embree to the filter below (the context first, so
// that Embree's pointer to it is one to this).
struct OcclusionQuery {
    RTCIntersectContext context;
    const Scene* scene = nullptr;
    float transmittance = 1.0f;
    // The Blend surfaces already counted: with spatial splits Embree may report one triangle
    // twice, and it must not dim the ray twice.
    static constexpr int kSeen = 32;
    unsigned seen[kSeen][2];
    int nseen = 0;
};

// Called by Embree for every candidate hit of an occlusion ray on a Mask or Blend mesh:
// rejecting the hit (valid = 0) lets the ray go on. Mask cut-outs are no surface; a Blend
// surface lets 1 − α through, and the ray is blocked once (almost) nothing gets through.
void occlusionFilter(const RTCFilterFunctionNArguments* args) {
    auto* query = reinterpret_cast<OcclusionQuery*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] == 0) continue;
        const unsigned geom =
            unsigned(meshOf(RTCHitN_instID(args->hit, args->N, i, 0),
                            RTCHitN_geomID(args->hit, args->N, i), query->scene->meshes.size()));
        const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        const SurfaceCoverage c =
            surfaceCoverage(*query->scene, int(geom), int(prim), RTCHitN_u(args->hit, args->N, i),
                            RTCHitN_v(args->hit, args->N, i));
        if (!c.present) {
            args->valid[i] = 0;
            continue;
        }
        if (c.alpha >= 1.0f) continue;
        bool counted = false;
        for (int k = 0; k < query->nseen; ++k)
            counted = counted || (query->seen[k][0] == geom && query->seen[k][1] == prim);
        if (!counted) {
            query->transmittance *= 1.0f - c.alpha;
            if (query->nseen < OcclusionQuery::kSeen) {
                query->seen[query->nseen][0] = geom;
                query->seen[query->nseen][1] = prim;
                ++query->nseen;
            }
        }
        if (query->transmittance > 1e-6f) args->valid[i] = 0;
    }
}

} // namespace

RayCaster::RayCaster(const Scene& scene, const std::vector<int>& moving)
    : m_impl(std::make_unique<Impl>()) {
    m_impl->source = &scene;
    // Embree picks the widest kernel the CPU has unless DHDR_EMBREE_ISA names one, so that
    // the tests can run under each (their float arithmetic differs in the last bits).
    const std::string isa = embreeIsaRequested();
    if (!isa.empty() && !embreeIsaSupported(isa)) {
        m_error = "DHDR_EMBREE_ISA=" + isa +
                  ": not an Embree kernel this CPU runs (sse2, sse4.2, avx, avx2, avx512)";
        return;
    }
    const std::string config = isa.empty() ? std::string() : "isa=" + isa;
    // Embree's own threads only build the BVH; they do not change which surface a ray hits.
    m_impl->device = rtcNewDevice(isa.empty() ? nullptr : config.c_str());
    if (!m_impl->device) {
        m_error = "cannot create an Embree device";
        return;
    }
    m_impl->scene = rtcNewScene(m_impl->device);
    rtcSetSceneBuildQuality(m_impl->scene, RTC_BUILD_QUALITY_HIGH);
    // Without the robust mode, 1 ray in 20 aimed along a shared edge slips between the two
    // triangles (RayOrigins.RaysThroughAClosedMeshsEdgesHitIt): a sphere with a hole.
    rtcSetSceneFlags(m_impl->scene, RTC_SCENE_FLAG_ROBUST);
    m_impl->meshes = scene.meshes.size();
    m_impl->vertices.resize(scene.meshes.size(), nullptr);
    m_impl->instanced.resize(scene.meshes.size(), nullptr);
    // A triangle geometry of `mesh` with its vertices at `at`, committed; its vertex buffer to
    // `buffer`.
    auto triangles = [&](const Mesh& mesh, const std::vector<glm::vec3>& at, bool refit,
                         float*& buffer) {
        RTCGeometry geom = rtcNewGeometry(m_impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        buffer = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), at.size()));
        for (size_t v = 0; v < at.size(); ++v)
            for (int c = 0; c < 3; ++c)
                buffer[3 * v + size_t(c)] = at[v][c];
        if (refit) rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_REFIT);
        auto* indices = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(unsigned), mesh.triangles.size()));
        for (size_t t = 0; t < mesh.triangles.size(); ++t)
            for (int c = 0; c < 3; ++c)
                indices[3 * t + size_t(c)] = mesh.triangles[t][c];
        if (scene.materials[size_t(mesh.material)].alphaMode != AlphaMode::Opaque) {
            rtcSetGeometryOccludedFilterFunction(geom, occlusionFilter);
            m_impl->transparent = true;
        }
        rtcCommitGeometry(geom);
        return geom;
    };
    for (size_t i = 0; i < scene.meshes.size(); ++i) {
        const Mesh& mesh = scene.meshes[i];
        const bool instance = mesh.instance && scene.rig && i < scene.rig->meshes.size() &&
                              scene.rig->meshes[i].positions.size() == mesh.positions.size();
        if (!instance) {
            // Deformed meshes keep their own BVH, refitted when their vertices move.
            const bool refit = std::find(moving.begin(), moving.end(), int(i)) != moving.end();
            RTCGeometry geom = triangles(mesh, mesh.positions, refit, m_impl->vertices[i]);
            rtcAttachGeometryByID(m_impl->scene, geom, unsigned(i));
            rtcReleaseGeometry(geom);
            continue;
        }
        // A rigid mover: its node-space triangles in a scene of their own, built once, and an
        // instance of it in the top scene, moved by its transform alone (docs/animation.md).
        RTCScene own = rtcNewScene(m_impl->device);
        rtcSetSceneBuildQuality(own, RTC_BUILD_QUALITY_HIGH);
        rtcSetSceneFlags(own, RTC_SCENE_FLAG_ROBUST);
        float* local = nullptr;
        RTCGeometry geom = triangles(mesh, scene.rig->meshes[i].positions, false, local);
        rtcAttachGeometryByID(own, geom, 0);
        rtcReleaseGeometry(geom);
        rtcCommitScene(own);
        m_impl->instanced[i] = own;
        m_impl->instances = true;
        RTCGeometry placed = rtcNewGeometry(m_impl->device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(placed, own);
        rtcAttachGeometryByID(m_impl->scene, placed, unsigned(i));
        rtcReleaseGeometry(placed);
        RTCGeometry standIn = triangles(mesh, mesh.positions, true, m_impl->vertices[i]);
        rtcAttachGeometryByID(m_impl->scene, standIn, unsigned(scene.meshes.size() + i));
        rtcReleaseGeometry(standIn);
        m_impl->place(unsigned(i), mesh);
    }
    rtcCommitScene(m_impl->scene);
    m_impl->takeBounds();
    m_plane = scene.hasGroundPlane;
    m_planeY = scene.groundPlaneY;
    if (rtcGetDeviceError(m_impl->device) != RTC_ERROR_NONE)
        m_error = "Embree could not build the scene";
}

RayCaster::~RayCaster() = default;

bool RayCaster::instanced(int mesh) const {
    return ok() && mesh >= 0 && size_t(mesh) < m_impl->instanced.size() &&
           m_impl->instanced[size_t(mesh)] != nullptr;
}

bool RayCaster::updateMeshes(const std::vector<int>& meshes) {
    if (!ok()) return false;
    const Scene& scene = *m_impl->source;
    for (const int i : meshes) {
        if (i < 0 || size_t(i) >= scene.meshes.size()) continue;
        const Mesh& mesh = scene.meshes[size_t(i)];
        if (m_impl->instanced[size_t(i)]) {
            if (mesh.instance) m_impl->place(unsigned(i), mesh);
            continue;
        }
        float* vertices = m_impl->vertices[size_t(i)];
        for (size_t v = 0; v < mesh.positions.size(); ++v)
            for (int c = 0; c < 3; ++c)
                vertices[3 * v + size_t(c)] = mesh.positions[v][c];
        RTCGeometry geom = rtcGetGeometry(m_impl->scene, unsigned(i));
        rtcUpdateGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(geom);
    }
    if (!meshes.empty()) {
        rtcCommitScene(m_impl->scene);
        m_impl->takeBounds();
    }
    if (rtcGetDeviceError(m_impl->device) != RTC_ERROR_NONE) {
        m_error = "Embree could not refit the moved meshes";
        return false;
    }
    return true;
}

bool RayCaster::bounds(glm::vec3& lower, glm::vec3& upper) const {
    if (!ok()) return false;
    for (int c = 0; c < 3; ++c) {
        if (!(m_impl->lower[c] <= m_impl->upper[c])) return false;
        // The widened bounds, rounded outwards to float.
        lower[c] = nextFloatDown(float(m_impl->lower[c]));
        upper[c] = nextFloatUp(float(m_impl->upper[c]));
    }
    return true;
}

const Scene& RayCaster::scene() const {
    return *m_impl->source;
}

RayHit RayCaster::intersect(const Ray& ray, double tnear) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = float(ray.origin.x);
    rh.ray.org_y = float(ray.origin.y);
    rh.ray.org_z = float(ray.origin.z);
    rh.ray.dir_x = float(ray.direction.x);
    rh.ray.dir_y = float(ray.direction.y);
    rh.ray.dir_z = float(ray.direction.z);
    rh.ray.tnear = float(tnear);
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.time = 0.0f;
    rh.ray.mask = ~0u;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    const float o[3] = {rh.ray.org_x, rh.ray.org_y, rh.ray.org_z},
                d[3] = {rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z};
    if (m_impl->mayHit(o, d, rh.ray.tnear, rh.ray.tfar))
        rtcIntersect1(m_impl->scene, &context, &rh);

    RayHit hit;
    if (m_plane && ray.direction.y != 0.0) {
        const double t = (double(m_planeY) - ray.origin.y) / ray.direction.y;
        if (t > tnear && (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || t < rh.ray.tfar)) {
            hit.hit = true;
            hit.t = t;
            hit.mesh = kGroundPlaneHit;
            return hit;
        }
    }
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
    hit.hit = true;
    hit.t = rh.ray.tfar;
    hit.mesh = meshOf(rh.hit.instID[0], rh.hit.geomID, m_impl->meshes);
    hit.triangle = int(rh.hit.primID);
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    return hit;
}

namespace {

void setRay(RTCRay& r, const glm::vec3& origin, const glm::vec3& direction, float tmax) {
    r.org_x = origin.x;
    r.org_y = origin.y;
    r.org_z = origin.z;
    r.dir_x = direction.x;
    r.dir_y = direction.y;
    r.dir_z = direction.z;
    r.tnear = 0.0f;
    r.tfar = tmax;
    r.time = 0.0f;
    r.mask = ~0u;
    r.id = 0;
    r.flags = 0;
}

} // namespace

float RayCaster::transmittance(const glm::vec3& origin, const glm::vec3& direction,
                               float tmax) const {
    if (blockedByPlane(origin, direction, tmax)) return 0.0f;
    const float o[3] = {origin.x, origin.y, origin.z},
                d[3] = {direction.x, direction.y, direction.z};
    if (!m_impl->mayHit(o, d, 0.0f, tmax)) return 1.0f;
    OcclusionQuery query;
    rtcInitIntersectContext(&query.context);
    query.scene = m_impl->source;
    RTCRay ray;
    setRay(ray, origin, direction, tmax);
    rtcOccluded1(m_impl->scene, &query.context, &ray);
    // Embree marks a blocked ray by setting tfar to −∞.
    return ray.tfar < 0.0f ? 0.0f : query.transmittance;
}

void RayCaster::test(const ShadowRay* rays, size_t count, float* transmittance) const {
    // One ray at a time when surfaces may let light through: each carries its own product.
    if (count == 1 || m_impl->transparent) {
        for (size_t i = 0; i < count; ++i)
            transmittance[i] = this->transmittance(rays[i].origin, rays[i].direction, rays[i].tmax);
        return;
    }
    // The ground plane first; rays that miss the triangles' bounds need nothing more; the rest
    // go to Embree in batches.
    constexpr size_t kBatch = 64;
    RTCRay batch[kBatch];
    size_t index[kBatch], n = 0;
    auto flush = [&] {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        rtcOccluded1M(m_impl->scene, &context, batch, unsigned(n), sizeof(RTCRay));
        for (size_t i = 0; i < n; ++i)
            if (batch[i].tfar < 0.0f) transmittance[index[i]] = 0.0f;
        n = 0;
    };
    for (size_t i = 0; i < count; ++i) {
        const ShadowRay& r = rays[i];
        transmittance[i] = blockedByPlane(r.origin, r.direction, r.tmax) ? 0.0f : 1.0f;
        const float o[3] = {r.origin.x, r.origin.y, r.origin.z},
                    d[3] = {r.direction.x, r.direction.y, r.direction.z};
        if (transmittance[i] == 0.0f || !m_impl->mayHit(o, d, 0.0f, r.tmax)) continue;
        setRay(batch[n], r.origin, r.direction, r.tmax);
        index[n++] = i;
        if (n == kBatch) flush();
    }
    if (n > 0) flush();
}

namespace {

// Embree's packet of W rays and its occlusion call.
template <int W>
struct Packet;
template <>
struct Packet<4> {
    using Rays = RTCRay4;
    static void occluded(const int* valid, RTCScene scene, RTCIntersectContext* context, Rays* r) {
        rtcOccluded4(valid, scene, context, r);
    }
};
template <>
struct Packet<8> {
    using Rays = RTCRay8;
    static void occluded(const int* valid, RTCScene scene, RTCIntersectContext* context, Rays* r) {
        rtcOccluded8(valid, scene, context, r);
    }
};
template <>
struct Packet<16> {
    using Rays = RTCRay16;
    static void occluded(const int* valid, RTCScene scene, RTCIntersectContext* context, Rays* r) {
        rtcOccluded16(valid, scene, context, r);
    }
};

} // namespace

template <int W>
void RayCaster::occludedPacket(const ShadowRay* rays, size_t n, float* transmittance) const {
    alignas(64) typename Packet<W>::Rays packet;
    alignas(64) int valid[W];
    bool any = false;
    for (size_t i = 0; i < size_t(W); ++i) {
        const ShadowRay& r = rays[std::min(i, n - 1)];
        const float o[3] = {r.origin.x, r.origin.y, r.origin.z},
                    d[3] = {r.direction.x, r.direction.y, r.direction.z};
        valid[i] = i < n && m_impl->mayHit(o, d, 0.0f, r.tmax) ? -1 : 0;
        any = any || valid[i] != 0;
        packet.org_x[i] = r.origin.x;
        packet.org_y[i] = r.origin.y;
        packet.org_z[i] = r.origin.z;
        packet.tnear[i] = 0.0f;
        packet.dir_x[i] = r.direction.x;
        packet.dir_y[i] = r.direction.y;
        packet.dir_z[i] = r.direction.z;
        packet.time[i] = 0.0f;
        packet.tfar[i] = r.tmax;
        packet.mask[i] = ~0u;
        packet.id[i] = unsigned(i);
        packet.flags[i] = 0;
    }
    if (any) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = m_impl->instances ? RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT
                                          : RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        Packet<W>::occluded(valid, m_impl->scene, &context, &packet);
    }
    for (size_t i = 0; i < n; ++i) {
        const ShadowRay& r = rays[i];
        const bool open = !(valid[i] != 0 && packet.tfar[i] < 0.0f) &&
                          !blockedByPlane(r.origin, r.direction, r.tmax);
        transmittance[i] = open ? 1.0f : 0.0f;
    }
}

void RayCaster::testCoherent(const ShadowRay* rays, size_t count, float* transmittance) const {
    if (m_impl->transparent) {
        test(rays, count, transmittance);
        return;
    }
    // Packets of 16, the last of 4 or 8 when that holds what is left: a packet costs about
    // its width whatever its live rays (a sun's 4 probe rays: the frame 4 % faster in packets
    // of 4 than in one of 16; bench/README.md, session 19).
    for (size_t begin = 0; begin < count;) {
        const size_t left = count - begin, n = std::min<size_t>(16, left);
        if (n <= 4)
            occludedPacket<4>(rays + begin, n, transmittance + begin);
        else if (n <= 8)
            occludedPacket<8>(rays + begin, n, transmittance + begin);
        else
            occludedPacket<16>(rays + begin, n, transmittance + begin);
        begin += n;
    }
}

bool RayCaster::mayBlockCone(const glm::vec3& apex, float radius, const glm::vec3& axis,
                             float halfAngle) const {
    // A little wider than asked, for the rounding of the directions sampled within it.
    const double angle = double(halfAngle) + 1e-4;
    const glm::dvec3 o(apex), a = glm::normalize(glm::dvec3(axis));
    const double r = double(radius);
    if (!(angle < 1.5) || !(r >= 0.0) || !std::isfinite(o.x + o.y + o.z + a.x + a.y + a.z))
        return true;
    // From above the ground plane, rays that all climb never reach it.
    if (m_plane && !(o.y - r > double(m_planeY) && a.y > std::sin(angle))) return true;
    const double* lower = m_impl->lower;
    const double* upper = m_impl->upper;
    if (!(lower[0] <= upper[0] && lower[1] <= upper[1] && lower[2] <= upper[2])) return false;
    // A ray that enters the box has gone at most D, the box's farthest point from the apex
    // plus the radius; there it lies within e = r + D·tan(angle) of the axis at the same
    // length: the axis's segment [0, D] must meet the box grown by e.
    double far2 = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double farthest = std::max(std::abs(o[c] - lower[c]), std::abs(o[c] - upper[c]));
        far2 += farthest * farthest;
    }
    const double D = std::sqrt(far2) + r;
    const double e = r + D * std::tan(angle) + 1e-6 * (1.0 + D);
    const double origin[3] = {o.x, o.y, o.z}, direction[3] = {a.x, a.y, a.z};
    return m_impl->meets(origin, direction, 0.0, D, e);
}

bool RayCaster::blockedByPlane(const glm::vec3& origin, const glm::vec3& direction,
                               float tmax) const {
    if (!m_plane || direction.y == 0.0f) return false;
    const float t = (m_planeY - origin.y) / direction.y;
    return t > 0.0f && t < tmax;
}

} // namespace dhdr
