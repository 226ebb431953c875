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

// How a lookup is filtered over the pixel's footprint in the texture, where one is known
// (GBufferParams::textureFilter): one bilinear lookup of the full-size image at its centre; the
// mip level whose texels match the footprint's longer side, blended with the next (trilinear,
// as GPUs and OpenImageIO's TextureSystem do by default); or up to 8 trilinear lookups along
// the footprint's longer axis at the level of its shorter one (anisotropic).
enum class TextureFilter { Bilinear, Trilinear, Anisotropic };

// One level of a texture's mip pyramid: RGBA texels, row by row from the image's top.
struct TextureLevel {
    int width = 0, height = 0;
    std::vector<float> rgba;            // float texels, when the codes are empty
    std::vector<std::uint8_t> codes8;   // 8-bit texels, RGBA
    std::vector<std::uint16_t> codes16; // 16-bit texels, RGBA
};

// A texture's RGBA texels, straight (not premultiplied) alpha. An 8- or 16-bit file's texels
// stay the file's codes (a quarter or half of float's memory), each turned into its linear
// value through a table as it is read (sRGB-decoded for colour textures); others are floats.
// The image itself is level 0; buildMipmaps() adds the smaller levels.
struct Texture : TextureLevel {
    std::string name;
    // Each code's linear value: the colour channels' and alpha's tables (256 or 65536 each).
    std::shared_ptr<const std::vector<float>> colorTable, alphaTable;
    std::vector<TextureLevel> mips; // levels 1, 2, …: each half the one before (buildMipmaps)
    // As a normal map: the mean length of its texels' vectors 2·RGB − 1 at level 0, which
    // quantisation keeps from 1 (meanNormalLength); a filtered texel's is measured against it.
    float normalLength = 1.0f;

    int levels() const { return 1 + int(mips.size()); }
    const TextureLevel& level(int k) const { return k == 0 ? *this : mips[size_t(k - 1)]; }

    // Texel i (y · width + x) of `level` as linear RGBA.
    glm::vec4 texel(const TextureLevel& level, size_t i) const {
        if (!level.codes8.empty()) return decoded(&level.codes8[4 * i]);
        if (!level.codes16.empty()) return decoded(&level.codes16[4 * i]);
        const float* p = &level.rgba[4 * i];
        return glm::vec4(p[0], p[1], p[2], p[3]);
    }
    glm::vec4 texel(size_t i) const { return texel(*this, i); }

    // Bilinear (or nearest) lookup of level 0, each texel index wrapped as `sampler` says, as
    // OpenGL does; uv (0, 0) is the image's top-left.
    glm::vec4 sample(glm::vec2 uv, const TextureSampler& sampler = {}) const;
    // The lookup filtered over the footprint whose sides are `dx` and `dy` (the change of uv
    // from the pixel to its neighbours) as `filter` says. A footprint smaller than a texel
    // (magnification) is the lookup above, exactly; so is everything without mip levels.
    glm::vec4 sample(glm::vec2 uv, glm::vec2 dx, glm::vec2 dy, const TextureSampler& sampler,
                     TextureFilter filter) const;
    // Whether that lookup reads mip levels: a footprint wider than a texel, and levels to read.
    bool minified(glm::vec2 dx, glm::vec2 dy, TextureFilter filter) const;

private:
    template <class Code>
    glm::vec4 decoded(const Code* p) const {
        const std::vector<float>& c = *colorTable;
        return glm::vec4(c[p[0]], c[p[1]], c[p[2]], (*alphaTable)[p[3]]);
    }
    glm::vec4 bilinear(const TextureLevel& level, glm::vec2 uv,
                       const TextureSampler& sampler) const;
    glm::vec4 trilinear(glm::vec2 uv, float lod, const TextureSampler& sampler) const;
};

// Fills texture.mips: level k + 1 is ⌊w/2⌋ × ⌊h/2⌋ of level k (at least 1 × 1), down to
// 1 × 1, each texel the exact box average of the linear values of the area it covers (its
// weights sum to 1, so every level keeps the image's mean), stored as level 0 is: codes
// rounded to the nearest code of the same table, or floats.
void buildMipmaps(Texture& texture, int nthreads = 0);

// The mean length of level 0's vectors 2·RGB − 1 (in double), for Texture::normalLength.
float meanNormalLength(const Texture& texture);

// KHR_texture_transform of one texture reference: uv' = T(offset) · R(rotation) · S(scale) · uv,
// in glTF's UV space (origin top-left).
struct TextureTransform {
    glm::vec2 offset{0.0f};
    float rotation = 0.0f; // radians, counter-clockwise
    glm::vec2 scale{1.0f};

    glm::vec2 apply(glm::vec2 uv) const;
    // The transform of a difference of two uvs (rotation and scale, no offset).
    glm::vec2 applyLinear(glm::vec2 d) const;
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
