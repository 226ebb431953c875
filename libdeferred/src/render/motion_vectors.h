// The motion layer of an animated G-buffer: where a surface point was one frame before and
// will be one frame after, in pixels, in Blender's Vector-pass convention (docs/animation.md).
#pragma once

#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/scene/frame_motion.h>

namespace dhdr {

struct Scene;

class MotionVectors {
public:
    // `now`: the camera of the frame rendered; the image is width × height.
    MotionVectors(const Scene& scene, const FrameMotion& motion, const Camera& now, int width,
                  int height);

    // The four values of the layer for the surface `hit` along `ray` (a miss: the direction at
    // infinity, moved by the camera's rotation alone): X Y = raster(previous) − raster(now),
    // Z W = raster(now) − raster(next). A half whose point is behind that frame's camera (or
    // not finite) is 0.
    void at(const Ray& ray, const RayHit& hit, float out[4]) const;

private:
    const Scene& m_scene;
    const FrameMotion& m_motion;
    glm::dmat4 m_previous, m_now, m_next; // world to NDC
    bool m_orthographic;
    double m_width, m_height;
};

} // namespace dhdr
