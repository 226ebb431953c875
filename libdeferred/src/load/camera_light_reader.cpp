#include "load/camera_light_reader.h"

#include "load/gltf_json.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <map>

namespace dhdr::detail {

namespace {

// A glTF camera as the file gives it (`g`): it sits at its node, looking down −Z.
void cameraFromFile(const GltfCamera& g, const glm::dmat4& world, SceneCamera& sc) {
    sc.camera.cameraToWorld = world;
    sc.problem = g.problem;
    sc.camera.orthographic = g.orthographic;
    sc.camera.znear = g.znear;
    if (g.orthographic) {
        sc.camera.ymag = g.ymag;
        sc.camera.zfar = g.zfar;
        sc.aspect = g.ymag != 0.0 ? g.xmag / g.ymag : 0.0;
        if (sc.problem.empty() && !(g.xmag > 0.0))
            sc.problem = "its xmag, " + std::to_string(g.xmag) + ", is not a positive number";
    } else {
        sc.camera.yfov = g.yfov;
        sc.aspect = g.aspectRatio;
        // No zfar (an infinite projection in glTF): Assimp's far plane, as before,
        // if it lies beyond the near one.
        if (g.zfar != 0.0)
            sc.camera.zfar = g.zfar;
        else if (!(sc.camera.zfar > g.znear))
            sc.camera.zfar = std::max(1000.0, 1000.0 * g.znear);
    }
}

// An unnamed node's glTF camera: Assimp's numbers. Assimp 5.2's glTF importer copies the
// node's translation into mPosition (applying it would move the camera twice) and reports
// yfov · aspect as mHorizontalFOV.
void cameraFromAssimpGltf(const aiCamera& ac, const glm::dmat4& world, SceneCamera& sc) {
    sc.camera.cameraToWorld = world;
    sc.camera.yfov = ac.mAspect > 0.0f ? ac.mHorizontalFOV / ac.mAspect : ac.mHorizontalFOV;
    // An orthographic glTF camera: Assimp gives xmag as mOrthographicWidth and
    // xmag / ymag as mAspect.
    if (ac.mOrthographicWidth > 0.0f) {
        sc.camera.orthographic = true;
        sc.camera.ymag =
            ac.mAspect > 0.0f ? ac.mOrthographicWidth / ac.mAspect : ac.mOrthographicWidth;
    }
}

// Assimp's documented convention: a camera in its node's space, and half the horizontal
// angle.
void cameraFromAssimp(const aiCamera& ac, const glm::dmat4& world, SceneCamera& sc) {
    const glm::dvec3 eye(ac.mPosition.x, ac.mPosition.y, ac.mPosition.z);
    const glm::dvec3 look(ac.mLookAt.x, ac.mLookAt.y, ac.mLookAt.z);
    const glm::dvec3 up(ac.mUp.x, ac.mUp.y, ac.mUp.z);
    sc.camera.cameraToWorld = world * glm::inverse(glm::lookAt(eye, eye + look, up));
    const double aspect = ac.mAspect > 0.0f ? ac.mAspect : 1.0;
    sc.camera.yfov = 2.0 * std::atan(std::tan(double(ac.mHorizontalFOV)) / aspect);
}

LightType lightType(aiLightSourceType type) {
    switch (type) {
    case aiLightSource_DIRECTIONAL:
        return LightType::Directional;
    case aiLightSource_SPOT:
        return LightType::Spot;
    case aiLightSource_AMBIENT:
        return LightType::Ambient;
    default:
        return LightType::Point;
    }
}

// A light's colour, intensity, range and cones: the file's (`g`) for glTF, else Assimp's,
// whose colour holds the intensity.
void lightFields(const aiLight& al, const GltfLight* g, Light& light) {
    if (g) {
        light.color = g->color;
        light.intensity = g->intensity;
        if (g->range > 0.0f) light.range = g->range;
        light.innerConeAngle = g->innerConeAngle;
        light.outerConeAngle = g->outerConeAngle;
    } else {
        const glm::vec3 c(al.mColorDiffuse.r, al.mColorDiffuse.g, al.mColorDiffuse.b);
        light.intensity = std::max({c.r, c.g, c.b});
        light.color = light.intensity > 0.0f ? c / light.intensity : glm::vec3(1.0f);
        light.innerConeAngle = al.mAngleInnerCone;
        light.outerConeAngle = al.mAngleOuterCone;
    }
}

} // namespace

void readCameras(const aiScene& ai, const nlohmann::json& doc, bool gltf, const NodeWorld& world,
                 Scene& scene, RigLoader& rig) {
    // Assimp 5.2 passes a glTF camera's numbers through floats, folds its aspect ratio into
    // the field of view and reports an absent zfar as a number: glTF cameras come from the
    // file itself (placement from the node), others from Assimp.
    const auto fromFile = gltf ? gltfCamerasByNode(doc) : std::map<std::string, GltfCamera>{};
    for (unsigned i = 0; i < ai.mNumCameras; ++i) {
        const aiCamera& ac = *ai.mCameras[i];
        const glm::dmat4 nodeWorld = world(ac.mName);
        SceneCamera sc;
        sc.name = ac.mName.C_Str();
        sc.aspect = ac.mAspect;
        sc.camera.znear = ac.mClipPlaneNear > 0.0f ? ac.mClipPlaneNear : 0.01;
        sc.camera.zfar = ac.mClipPlaneFar > sc.camera.znear ? ac.mClipPlaneFar : 1000.0;
        const auto file = fromFile.find(sc.name);
        if (file != fromFile.end())
            cameraFromFile(file->second, nodeWorld, sc);
        else if (gltf)
            cameraFromAssimpGltf(ac, nodeWorld, sc);
        else
            cameraFromAssimp(ac, nodeWorld, sc);
        if (sc.problem.empty()) sc.problem = sc.camera.problem();
        if (sc.problem.empty() && !(std::isfinite(sc.aspect) && sc.aspect >= 0.0))
            sc.problem = "its aspect ratio is not a positive number";
        if (!sc.problem.empty())
            scene.warnings.push_back("camera '" + sc.name +
                                     "' cannot be rendered from: " + sc.problem);
        scene.cameras.push_back(sc);
        // A glTF camera sits at its node: it moves with it (others are not animated).
        rig.keepCamera(ac.mName);
    }
}

bool readLights(const aiScene& ai, const std::string& path, const nlohmann::json& doc, bool gltf,
                const NodeWorld& world, Scene& scene, RigLoader& rig, std::string& error) {
    // Assimp 5.2 folds a glTF light's intensity into its colour and drops its range, so
    // for glTF the light's own fields come from the file; placement from the node.
    std::map<std::string, GltfLight> fromFile;
    if (gltf && !gltfLightsByNode(doc, fromFile, error)) {
        error = path + ": " + error;
        return false;
    }
    for (unsigned i = 0; i < ai.mNumLights; ++i) {
        const aiLight& al = *ai.mLights[i];
        const glm::dmat4 nodeWorld = world(al.mName);
        Light light;
        light.name = al.mName.C_Str();
        light.position =
            glm::vec3(nodeWorld * glm::dvec4(al.mPosition.x, al.mPosition.y, al.mPosition.z, 1.0));
        const glm::dvec3 dir(nodeWorld *
                             glm::dvec4(al.mDirection.x, al.mDirection.y, al.mDirection.z, 0.0));
        light.direction =
            glm::length(dir) > 0.0 ? glm::vec3(glm::normalize(dir)) : glm::vec3(0.0f, 0.0f, -1.0f);
        light.type = lightType(al.mType);
        const auto it = fromFile.find(light.name);
        lightFields(al, it != fromFile.end() ? &it->second : nullptr, light);
        if (light.type == LightType::Ambient) continue;
        scene.lights.push_back(light);
        rig.keepLight(al);
    }
    return true;
}

} // namespace dhdr::detail
