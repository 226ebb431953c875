#include <algorithm>
#include <cmath>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr {

glm::vec2 TextureTransform::apply(glm::vec2 uv) const {
    // KHR_texture_transform: translation · rotation · scale, with the rotation's sign as
    // Khronos' TextureTransformTest model checks it (its arrow must point at the green
    // marker, docs/scenes.md): u' = cos r·u + sin r·v, v' = −sin r·u + cos r·v.
    const glm::vec2 s = uv * scale;
    const float c = std::cos(rotation), n = std::sin(rotation);
    return glm::vec2(c * s.x + n * s.y, -n * s.x + c * s.y) + offset;
}

glm::vec4 Texture::sample(glm::vec2 uv) const {
    if (width <= 0 || height <= 0) return glm::vec4(1.0f);
    const float x = (uv.x - std::floor(uv.x)) * float(width) - 0.5f;
    const float y = (uv.y - std::floor(uv.y)) * float(height) - 0.5f;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const float tx = x - float(x0), ty = y - float(y0);
    auto texel = [&](int xi, int yi) {
        xi = ((xi % width) + width) % width;
        yi = ((yi % height) + height) % height;
        const float* p = &rgba[(size_t(yi) * size_t(width) + size_t(xi)) * 4];
        return glm::vec4(p[0], p[1], p[2], p[3]);
    };
    return glm::mix(glm::mix(texel(x0, y0), texel(x0 + 1, y0), tx),
                    glm::mix(texel(x0, y0 + 1), texel(x0 + 1, y0 + 1), tx), ty);
}

float surfaceAlpha(const Scene& scene, int mesh, int triangle, float u, float v) {
    const Mesh& m = scene.meshes[size_t(mesh)];
    const Material& material = scene.materials[size_t(m.material)];
    float alpha = material.alpha;
    const TextureRef& ref = material.baseColorTexture;
    if (ref.texture >= 0 && !m.uvs.empty()) {
        const glm::uvec3 t = m.triangles[size_t(triangle)];
        const glm::vec2 uv = (1.0f - u - v) * m.uvs[t[0]] + u * m.uvs[t[1]] + v * m.uvs[t[2]];
        alpha *= scene.textures[size_t(ref.texture)].sample(ref.transform.apply(uv)).a;
    }
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
