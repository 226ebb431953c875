#include <cstdio>
#include <dhdr/deferred/scene/scene_info.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <filesystem>
#include <glm/gtc/constants.hpp>

namespace dhdr {

namespace {

std::string format(const char* fmt, double a, double b = 0, double c = 0, double d = 0,
                   double e = 0, double f = 0) {
    char text[256];
    std::snprintf(text, sizeof text, fmt, a, b, c, d, e, f);
    return text;
}

// A material's lines of --info: its factors, then its textures and extensions when it has any.
std::string describeMaterial(const Scene& scene, int index) {
    const Material& m = scene.materials[size_t(index)];
    std::string out = "    " + (m.name.empty() ? std::string("(unnamed)") : m.name) +
                      format(": base colour (%.3g, %.3g, %.3g), metallic %.3g, roughness %.3g",
                             m.baseColor.r, m.baseColor.g, m.baseColor.b, m.metallic, m.roughness);
    if (m.alphaMode != AlphaMode::Opaque)
        out += format(", alpha %.3g (", m.alpha) + alphaModeName(m.alphaMode) +
               (m.alphaMode == AlphaMode::Mask ? format(", cutoff %.3g)", m.alphaCutoff) : ")");
    if (m.emission != glm::vec3(0.0f))
        out += format(", emission (%.3g, %.3g, %.3g)", m.emission.r, m.emission.g, m.emission.b);
    if (m.clearcoat > 0.0f)
        out += format(", clearcoat %.3g (roughness %.3g)", m.clearcoat, m.clearcoatRoughness);
    if (m.sheen())
        out += format(", sheen (%.3g, %.3g, %.3g) (roughness %.3g)", m.sheenColor.r, m.sheenColor.g,
                      m.sheenColor.b, m.sheenRoughness);
    if (m.transmission > 0.0f) out += format(", transmission %.3g", m.transmission);
    if (m.absorbs())
        out += format(", volume absorbing to (%.3g, %.3g, %.3g) over %.3g", m.attenuationColor.r,
                      m.attenuationColor.g, m.attenuationColor.b, m.attenuationDistance);
    // Converted per texel: the base colour above is the diffuse colour, not yet dimmed.
    if (m.specularGlossinessTexture.texture >= 0)
        out +=
            format(", specular-glossiness per texel: specular (%.3g, %.3g, %.3g), glossiness %.3g",
                   m.glossSpecular.r, m.glossSpecular.g, m.glossSpecular.b, m.glossiness);
    out += "\n";
    std::string textures;
    for (const MaterialTexture& t : materialTextures(m)) {
        const std::string& name = scene.textures[size_t(t.ref->texture)].name;
        textures += std::string(textures.empty() ? "" : ", ") + t.slot + " " +
                    std::filesystem::path(name).filename().string();
    }
    if (!textures.empty()) out += "      textures: " + textures + "\n";
    const auto ext = scene.materialExtensions.find(index);
    if (ext != scene.materialExtensions.end()) {
        std::string names;
        for (const MaterialExtension& e : ext->second)
            names += (names.empty() ? "" : ", ") + e.name + (e.rendered ? "" : " (not read)");
        out += "      extensions: " + names + "\n";
    }
    return out;
}

} // namespace

const char* alphaModeName(AlphaMode mode) {
    switch (mode) {
    case AlphaMode::Opaque:
        return "opaque";
    case AlphaMode::Mask:
        return "mask";
    case AlphaMode::Blend:
        return "blend";
    }
    return "";
}

std::vector<int> materialsInUse(const Scene& scene) {
    std::vector<bool> used(scene.materials.size(), false);
    for (const Mesh& m : scene.meshes)
        if (m.material >= 0 && size_t(m.material) < used.size()) used[size_t(m.material)] = true;
    if (scene.hasGroundPlane && scene.groundMaterial >= 0)
        used[size_t(scene.groundMaterial)] = true;
    std::vector<int> out;
    for (size_t i = 0; i < used.size(); ++i)
        if (used[i]) out.push_back(int(i));
    return out;
}

std::vector<MaterialTexture> materialTextures(const Material& m) {
    const MaterialTexture all[] = {
        {"base colour", "base_color", &m.baseColorTexture},
        {"emissive", "emissive", &m.emissiveTexture},
        {"normal", "normal", &m.normalTexture},
        {"metallic-roughness", "metallic_roughness", &m.metallicRoughnessTexture},
        {"occlusion", "occlusion", &m.occlusionTexture},
        {"clearcoat", "clearcoat", &m.clearcoatTexture},
        {"clearcoat roughness", "clearcoat_roughness", &m.clearcoatRoughnessTexture},
        {"clearcoat normal", "clearcoat_normal", &m.clearcoatNormalTexture},
        {"sheen colour", "sheen_color", &m.sheenColorTexture},
        {"sheen roughness", "sheen_roughness", &m.sheenRoughnessTexture},
        {"specular", "specular", &m.specularTexture},
        {"specular colour", "specular_color", &m.specularColorTexture},
        {"specular-glossiness", "specular_glossiness", &m.specularGlossinessTexture},
        {"transmission", "transmission", &m.transmissionTexture}};
    std::vector<MaterialTexture> out;
    for (const MaterialTexture& t : all)
        if (t.ref->texture >= 0) out.push_back(t);
    return out;
}

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
    const std::vector<int> used = materialsInUse(scene);
    out += "  materials   " + std::to_string(used.size()) + "\n";
    for (const int i : used)
        out += describeMaterial(scene, i);
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
