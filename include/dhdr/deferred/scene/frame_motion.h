// What the motion layer is computed from: the scene and camera one frame either side.
#pragma once

#include <dhdr/deferred/scene/camera.h>
#include <glm/glm.hpp>
#include <vector>

namespace dhdr {

// Where the scene's surfaces and camera are at the frames before and after the one rendered:
// each mesh's vertex positions (one list per Scene::meshes entry, the same triangles), and the
// camera.
struct FrameMotion {
    std::vector<std::vector<glm::vec3>> previous, next;
    Camera previousCamera, nextCamera;
    // False where that frame has no camera to render from: that half of the layer is 0.
    bool hasPrevious = true, hasNext = true;
};

} // namespace dhdr
