#include "render/motion_vectors.h"

#include <cmath>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr {

MotionVectors::MotionVectors(const Scene& scene, const FrameMotion& motion, const Camera& now,
                             int width, int height)
    : m_scene(scene), m_motion(motion), m_orthographic(now.orthographic), m_width(width),
      m_height(height) {
    const double aspect = double(width) / double(height);
    m_previous = motion.previousCamera.worldToNDC(aspect);
    m_now = now.worldToNDC(aspect);
    m_next = motion.nextCamera.worldToNDC(aspect);
}

namespace {

// Pixel coordinates (x right, y up) of homogeneous point p under worldToNDC m; false behind
// the camera.
bool raster(const glm::dmat4& m, const glm::dvec4& p, double width, double height,
            glm::dvec2& out) {
    const glm::dvec4 clip = m * p;
    if (!(clip.w > 0.0)) return false;
    out = glm::dvec2((clip.x / clip.w + 1.0) * 0.5 * width, (clip.y / clip.w + 1.0) * 0.5 * height);
    return std::isfinite(out.x) && std::isfinite(out.y);
}

// The point at barycentrics (u, v) of triangle `t` of vertices `p`: the same formula for every
// frame, so that a point that does not move gives the same bits, and a motion of exactly 0.
glm::dvec3 pointOn(const std::vector<glm::vec3>& p, const glm::uvec3& t, double u, double v) {
    return (1.0 - u - v) * glm::dvec3(p[t.x]) + u * glm::dvec3(p[t.y]) + v * glm::dvec3(p[t.z]);
}

} // namespace

void MotionVectors::at(const Ray& ray, const RayHit& hit, float out[4]) const {
    glm::dvec4 before, now, after;
    if (!hit.hit) {
        // The background: a direction (w = 0), which only the camera's rotation moves. An
        // orthographic camera sees no direction at infinity: 0.
        if (m_orthographic) {
            out[0] = out[1] = out[2] = out[3] = 0.0f;
            return;
        }
        before = now = after = glm::dvec4(ray.direction, 0.0);
    } else if (hit.mesh == kGroundPlaneHit) {
        before = now = after = glm::dvec4(ray.origin + hit.t * ray.direction, 1.0);
    } else {
        const size_t m = size_t(hit.mesh);
        const glm::uvec3 t = m_scene.meshes[m].triangles[size_t(hit.triangle)];
        now = glm::dvec4(pointOn(m_scene.meshes[m].positions, t, hit.u, hit.v), 1.0);
        before = glm::dvec4(pointOn(m_motion.previous[m], t, hit.u, hit.v), 1.0);
        after = glm::dvec4(pointOn(m_motion.next[m], t, hit.u, hit.v), 1.0);
    }
    glm::dvec2 rPrev, rNow, rNext;
    const bool seen = raster(m_now, now, m_width, m_height, rNow);
    const bool back =
        seen && m_motion.hasPrevious && raster(m_previous, before, m_width, m_height, rPrev);
    const bool ahead = seen && m_motion.hasNext && raster(m_next, after, m_width, m_height, rNext);
    const glm::dvec2 xy = back ? rPrev - rNow : glm::dvec2(0.0);
    const glm::dvec2 zw = ahead ? rNow - rNext : glm::dvec2(0.0);
    const double fmax = 3.0e38; // a float's range: never Inf
    const double v[4] = {xy.x, xy.y, zw.x, zw.y};
    for (int c = 0; c < 4; ++c)
        out[c] = std::isfinite(v[c]) ? float(std::clamp(v[c], -fmax, fmax)) : 0.0f;
}

} // namespace dhdr
