// Closest-hit ray casting against a Scene's triangles (Embree behind a small interface, so
// that Embree's headers stay out of everything that includes this one).
#pragma once

#include <dhdr/deferred/camera.h>
#include <memory>
#include <string>

namespace dhdr {

struct Scene;

struct RayHit {
    bool hit = false;
    double t = 0.0;
    int mesh = -1;            // index into Scene::meshes
    int triangle = -1;        // index into that mesh's triangles
    float u = 0.0f, v = 0.0f; // barycentrics of vertices 1 and 2
};

class RayCaster {
public:
    // Builds the acceleration structure; `scene` must outlive the caster.
    explicit RayCaster(const Scene& scene);
    ~RayCaster();
    RayCaster(const RayCaster&) = delete;
    RayCaster& operator=(const RayCaster&) = delete;

    // False with a message when Embree could not be set up.
    bool ok() const { return m_error.empty(); }
    const std::string& error() const { return m_error; }

    // Closest hit along `ray` in (tnear, ∞). Safe to call from many threads.
    RayHit intersect(const Ray& ray, double tnear = 0.0) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    std::string m_error;
};

} // namespace dhdr
