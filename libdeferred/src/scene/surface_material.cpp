// A scene's surfaces as their materials make them: the UVs and vertex colours of a hit, its
// textures looked up, its coverage.
#include <algorithm>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr {

MeshUvs meshUvs(const Mesh& mesh, int triangle, double w1, double w2) {
    const glm::uvec3 t = mesh.triangles[size_t(triangle)];
    const float b1 = float(w1), b2 = float(w2), b0 = float(1.0 - w1 - w2);
    auto at = [&](const std::vector<glm::vec2>& uv) {
        return b0 * uv[t[0]] + b1 * uv[t[1]] + b2 * uv[t[2]];
    };
    MeshUvs out;
    if (!mesh.uvs.empty()) out.set[0] = at(mesh.uvs);
    out.set[1] = mesh.uvs1.empty() ? out.set[0] : at(mesh.uvs1);
    return out;
}

bool textureMinified(const Scene& scene, const TextureRef& ref, const MeshUvs& uvs) {
    if (!uvs.footprint) return false;
    const int set = ref.texCoord == 1 ? 1 : 0;
    const UvFootprint& f = *uvs.footprint;
    return scene.textures[size_t(ref.texture)].minified(
        ref.transform.applyLinear(f.dx[set]), ref.transform.applyLinear(f.dy[set]), f.filter);
}

glm::vec4 sampleTexture(const Scene& scene, const TextureRef& ref, const MeshUvs& uvs) {
    const int set = ref.texCoord == 1 ? 1 : 0;
    const Texture& texture = scene.textures[size_t(ref.texture)];
    const glm::vec2 uv = ref.transform.apply(uvs.set[set]);
    if (!uvs.footprint) return texture.sample(uv, ref.sampler);
    const UvFootprint& f = *uvs.footprint;
    return texture.sample(uv, ref.transform.applyLinear(f.dx[set]),
                          ref.transform.applyLinear(f.dy[set]), ref.sampler, f.filter);
}

glm::vec4 vertexColor(const Mesh& mesh, int triangle, double w1, double w2) {
    if (mesh.colors.empty()) return glm::vec4(1.0f);
    const glm::uvec3 t = mesh.triangles[size_t(triangle)];
    return float(1.0 - w1 - w2) * mesh.colors[t[0]] + float(w1) * mesh.colors[t[1]] +
           float(w2) * mesh.colors[t[2]];
}

glm::vec3 dielectricF0(float ior, const glm::vec3& specularColor, float specular) {
    const float r = (ior - 1.0f) / (ior + 1.0f);
    return glm::min(r * r * specularColor, glm::vec3(1.0f)) * specular;
}

glm::vec3 Material::dielectricF0() const {
    if (!dielectricSet) return glm::vec3(0.04f);
    return dhdr::dielectricF0(ior, specularColor, specularFactor);
}

MetalRoughFromSpecGloss specGlossAsMetalRough(const glm::vec3& diffuse, const glm::vec3& specular,
                                              float glossiness) {
    const float specularMax = std::max({specular.r, specular.g, specular.b});
    return {diffuse * (1.0f - specularMax), 1.0f - glossiness, specular};
}

float surfaceAlpha(const Scene& scene, int mesh, int triangle, float u, float v) {
    const Mesh& m = scene.meshes[size_t(mesh)];
    const Material& material = scene.materials[size_t(m.material)];
    float alpha = material.alpha * vertexColor(m, triangle, u, v).a;
    const TextureRef& ref = material.baseColorTexture;
    if (ref.texture >= 0 && !m.uvs.empty())
        alpha *= sampleTexture(scene, ref, meshUvs(m, triangle, u, v)).a;
    return std::clamp(alpha, 0.0f, 1.0f);
}

SurfaceCoverage surfaceCoverage(const Scene& scene, int mesh, int triangle, float u, float v) {
    const Material& material = scene.materials[size_t(scene.meshes[size_t(mesh)].material)];
    if (material.alphaMode == AlphaMode::Opaque) return {};
    const float alpha = surfaceAlpha(scene, mesh, triangle, u, v);
    if (material.alphaMode == AlphaMode::Mask) return {alpha >= material.alphaCutoff, 1.0f};
    return {alpha > 0.0f, alpha};
}

} // namespace dhdr
