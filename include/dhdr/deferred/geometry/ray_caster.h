// Scene queries against a Scene's triangles: closest hits for primary rays (dhdr-gbuffer),
// occlusion for shadow and AO rays (dhdr-light). Embree sits behind a small interface, so that
// its headers stay out of everything that includes this one.
#pragma once

#include <dhdr/deferred/core/visibility.h>
#include <dhdr/deferred/scene/camera.h>
#include <memory>
#include <string>
#include <vector>

namespace dhdr {

struct Scene;

struct RayHit {
    bool hit = false;
    double t = 0.0;
    int mesh = -1;            // index into Scene::meshes; kGroundPlaneHit: the ground plane
    int triangle = -1;        // index into that mesh's triangles
    float u = 0.0f, v = 0.0f; // barycentrics of vertices 1 and 2
};

inline constexpr int kGroundPlaneHit = -2;

class RayCaster : public Visibility {
public:
    // Builds the acceleration structure; `scene` must outlive the caster. A mesh that moves as
    // a whole (Mesh::instance, set by ScenePoser) is traced as an Embree instance of its
    // node-space triangles (SceneRig::meshes); `moving`: the other meshes whose vertices
    // updateMeshes may move (skins, morph targets), given a BVH that can be refitted.
    explicit RayCaster(const Scene& scene, const std::vector<int>& moving = {});
    ~RayCaster() override;
    RayCaster(const RayCaster&) = delete;
    RayCaster& operator=(const RayCaster&) = delete;

    // False with a message when Embree could not be set up.
    bool ok() const { return m_error.empty(); }
    const std::string& error() const { return m_error; }
    // The scene whose triangles the caster traces (surfaceAt of its hits).
    const Scene& scene() const;

    // Takes the scene's current state of `meshes`: an instanced mesh's transform
    // (Mesh::instance), the other meshes' vertices, whose BVH is refitted
    // (RTC_BUILD_QUALITY_REFIT): an animated scene's next frame without building it again.
    // Not safe while another thread traces.
    bool updateMeshes(const std::vector<int>& meshes);

    // Whether mesh `mesh` is traced as an instance (Mesh::instance).
    bool instanced(int mesh) const;

    // A box that holds every triangle (not the ground plane): a ray that misses it hits no
    // triangle. False when there is none.
    bool bounds(glm::vec3& lower, glm::vec3& upper) const;

    // Closest hit along `ray` in (tnear, ∞), the scene's ground plane included. Safe to call
    // from many threads.
    RayHit intersect(const Ray& ray, double tnear = 0.0) const;

    // The share of light that gets through the segment from `origin` along unit `direction`
    // within (0, tmax) (rtcOccluded1): 0 behind an opaque triangle, the product of (1 − α) of
    // the Blend surfaces crossed, Mask surfaces counted only where they are not cut out. Safe
    // to call from many threads.
    float transmittance(const glm::vec3& origin, const glm::vec3& direction, float tmax) const;

    // Many rays at once: through rtcOccluded1M when every surface is opaque, which traces a
    // batch of incoherent rays faster than one call per ray (bench/occlusion.cpp measures
    // both: 16 vs 12 M rays/s here), else one at a time.
    void test(const ShadowRay* rays, size_t count, float* transmittance) const override;

    // The same for rays that run side by side (a tile's rays towards one light), in coherent
    // packets of 16 (rtcOccluded16), the last of 4 or 8 when that holds the rest (a packet
    // costs its width, live rays or not); bench/occlusion.cpp compares it with test().
    void testCoherent(const ShadowRay* rays, size_t count, float* transmittance) const override;

    // False when the cone's rays all miss the triangles' bounds (and do not reach the ground
    // plane): its axis, within reach of the bounds grown by how far the cone spreads there.
    bool mayBlockCone(const glm::vec3& apex, float radius, const glm::vec3& axis,
                      float halfAngle) const override;

private:
    // n ≤ W rays in one Embree packet of W (4, 8 or 16).
    template <int W>
    void occludedPacket(const ShadowRay* rays, size_t n, float* transmittance) const;
    // Whether the ground plane lies on the segment (0, tmax) of the ray.
    bool blockedByPlane(const glm::vec3& origin, const glm::vec3& direction, float tmax) const;
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    bool m_plane = false;
    float m_planeY = 0.0f;
    std::string m_error;
};

} // namespace dhdr
