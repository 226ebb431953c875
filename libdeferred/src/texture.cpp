#include <algorithm>
#include <cmath>
#include <dhdr/deferred/scene.h>

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

} // namespace dhdr
