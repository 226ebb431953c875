// A scene's textures: their texels, how a material refers to one (UV set, transform, sampler)
// and how it is looked up.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

namespace dhdr {

// How a texture is looked up outside [0, 1] and between texels (glTF 2.0 §3.8.4 samplers).
enum class TextureWrap { Repeat, ClampToEdge, MirroredRepeat };
struct TextureSampler {
    TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat; // along u, along v
    bool nearest = false; // magFilter NEAREST: the texel itself, no bilinear blend
};

// A texture's RGBA texels, straight (not premultiplied) alpha. An 8- or 16-bit file's texels
// stay the file's codes (a quarter or half of float's memory), each turned into its linear
// value through a table as it is read (sRGB-decoded for colour textures); others are floats.
struct Texture {
    std::string name;
    int width = 0, height = 0;
    std::vector<float> rgba;            // float texels, when the codes are empty
    std::vector<std::uint8_t> codes8;   // 8-bit texels, RGBA
    std::vector<std::uint16_t> codes16; // 16-bit texels, RGBA
    // Each code's linear value: the colour channels' and alpha's tables (256 or 65536 each).
    std::shared_ptr<const std::vector<float>> colorTable, alphaTable;

    // Texel i (y · width + x) as linear RGBA.
    glm::vec4 texel(size_t i) const {
        if (!codes8.empty()) return decoded(&codes8[4 * i]);
        if (!codes16.empty()) return decoded(&codes16[4 * i]);
        const float* p = &rgba[4 * i];
        return glm::vec4(p[0], p[1], p[2], p[3]);
    }

    // Bilinear (or nearest) lookup, each texel index wrapped as `sampler` says, as OpenGL
    // does; uv (0, 0) is the image's top-left.
    glm::vec4 sample(glm::vec2 uv, const TextureSampler& sampler = {}) const;

private:
    template <class Code>
    glm::vec4 decoded(const Code* p) const {
        const std::vector<float>& c = *colorTable;
        return glm::vec4(c[p[0]], c[p[1]], c[p[2]], (*alphaTable)[p[3]]);
    }
};

// KHR_texture_transform of one texture reference: uv' = T(offset) · R(rotation) · S(scale) · uv,
// in glTF's UV space (origin top-left).
struct TextureTransform {
    glm::vec2 offset{0.0f};
    float rotation = 0.0f; // radians, counter-clockwise
    glm::vec2 scale{1.0f};

    glm::vec2 apply(glm::vec2 uv) const;
};

// A material's use of a texture: which one (−1: none), on which UV set, how its UVs are
// transformed and how it is sampled.
struct TextureRef {
    int texture = -1; // index into Scene::textures
    int texCoord = 0; // TEXCOORD_n: 0 (Mesh::uvs) or 1 (Mesh::uvs1)
    TextureTransform transform;
    TextureSampler sampler;
};

} // namespace dhdr
