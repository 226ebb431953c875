#include <cstdio>
#include <dhdr/deferred/scene/scene_info.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <glm/gtc/constants.hpp>

namespace dhdr {

namespace {

std::string format(const char* fmt, double a, double b = 0, double c = 0, double d = 0,
                   double e = 0, double f = 0) {
    char text[256];
    std::snprintf(text, sizeof text, fmt, a, b, c, d, e, f);
    return text;
}

} // namespace

std::string describeScene(const Scene& scene, const std::string& path) {
    size_t triangles = 0;
    for (const Mesh& m : scene.meshes)
        triangles += m.triangles.size();
    const glm::dvec3 lo = scene.boundsMin(), hi = scene.boundsMax();
    std::string out = path + "\n";
    out +=
        format("  bounds      (%g, %g, %g) to (%g, %g, %g)\n", lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
    out += "  objects     " + std::to_string(scene.objectNames.size()) + ", " +
           std::to_string(triangles) + " triangles\n";
    out += "  cameras     " + std::to_string(scene.cameras.size()) + "\n";
    for (const SceneCamera& c : scene.cameras) {
        const glm::dvec3 p = c.camera.position();
        out += "    " + c.name + ": " +
               (c.camera.orthographic ? format("orthographic, %g units high", 2.0 * c.camera.ymag)
                                      : format("perspective, vertical fov %.4g degrees",
                                               glm::degrees(c.camera.yfov))) +
               format(", at (%g, %g, %g)", p.x, p.y, p.z) +
               (c.problem.empty() ? "" : "; unusable: " + c.problem) + "\n";
    }
    out += "  lights      " + std::to_string(scene.lights.size()) + "\n";
    for (const Light& l : scene.lights)
        out += "    " + (l.name.empty() ? std::string("(unnamed)") : l.name) + ": " +
               lightTypeName(l.type) +
               format(", intensity %g, at (%g, %g, %g)\n", l.intensity, l.position.x, l.position.y,
                      l.position.z);
    out += "  materials   " + std::to_string(scene.materials.size()) + "\n";
    for (const Material& m : scene.materials) {
        std::string textures;
        if (m.baseColorTexture.texture >= 0) textures += " base-colour";
        if (m.emissiveTexture.texture >= 0) textures += " emissive";
        if (m.normalTexture.texture >= 0) textures += " normal";
        out += "    " + (m.name.empty() ? std::string("(unnamed)") : m.name) +
               format(": base colour (%.3g, %.3g, %.3g), metallic %.3g, roughness %.3g",
                      m.baseColor.r, m.baseColor.g, m.baseColor.b, m.metallic, m.roughness) +
               (textures.empty() ? "" : ", textures:" + textures) + "\n";
    }
    if (scene.rig) {
        // What --animation chooses among, with the times --frames and --fps reach.
        out += "  animations  " + std::to_string(scene.rig->animations.size()) + "\n";
        for (size_t i = 0; i < scene.rig->animations.size(); ++i) {
            const Animation& a = scene.rig->animations[i];
            out += "    " + std::to_string(i) + " '" + a.name + "': " +
                   (a.problem.empty()
                        ? format("%g s (keys from %g to %g s), ", a.duration(), a.start, a.end) +
                              std::to_string(a.channels.size()) + " channels"
                        : "unusable: " + a.problem) +
                   "\n";
        }
    }
    out += "  left out    " + std::string(scene.warnings.empty() ? "nothing\n" : "\n");
    for (const std::string& w : scene.warnings)
        out += "    " + w + "\n";
    return out;
}

} // namespace dhdr
