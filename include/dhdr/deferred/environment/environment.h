// Equirectangular HDR environments: the light arriving from every direction.
#pragma once

#include <OpenImageIO/oiioversion.h>
#include <glm/glm.hpp>
#include <string>
#include <vector>

OIIO_NAMESPACE_BEGIN
class ImageSpec;
OIIO_NAMESPACE_END

namespace dhdr {

// Where a unit direction d of the scene's frame (Y up) lies in an equirectangular image:
// u = 0.5 + atan2(d.z, d.x) / 2π from the left edge, t = acos(d.y) / π from the top edge, as
// Blender's Environment Texture maps a scene that Blender exports to glTF (docs/ibl.md).
glm::vec2 equirectUV(const glm::vec3& d);
// The unit direction at (u, t), the inverse of equirectUV.
glm::vec3 equirectDirection(glm::vec2 uv);

// An equirectangular image of scene-linear radiance, RGB float, rows from the top.
struct EnvironmentImage {
    int width = 0, height = 0;
    std::vector<float> rgb;

    glm::vec3 texel(int x, int y) const {
        const float* p = &rgb[3 * (size_t(y) * size_t(width) + size_t(x))];
        return {p[0], p[1], p[2]};
    }
    // Bilinear between texel centres, wrapping in u, clamped in t.
    glm::vec3 bilinear(glm::vec2 uv) const;
    glm::vec3 radiance(const glm::vec3& d) const { return bilinear(equirectUV(d)); }
    // The solid angle of row y's texels.
    double texelSolidAngle(int y) const;
    // A quarter-size image, each texel the solid-angle-weighted mean of four.
    EnvironmentImage downsampled() const;
};

// The largest environment read, in texels: 16384 × 8192 (the largest HDRIs published, 1.5 GiB
// as float RGB); a larger header is refused before anything is allocated.
inline constexpr long long kMaxEnvironmentTexels = 16384LL * 8192LL;

// Reads subimage `subimage` of an image OpenImageIO reads as an environment: 2:1, at most
// kMaxEnvironmentTexels. Colour by channel name: R, G, B; else a luminance channel Y (or a
// single unnamed one) as grey, its alpha ignored; else the first three channels. NaN and ±Inf
// texels are replaced by 0 and counted in `replaced`. False with `error` saying why (without
// the path).
bool readEnvironmentImage(const std::string& path, EnvironmentImage& env, std::string& error,
                          long long* replaced = nullptr, int subimage = 0);

// The same from float pixels held in memory (interleaved, spec.nchannels a texel, channels
// named by `spec`): the Python module's environments that were never written to a file.
bool environmentFromPixels(const OIIO::ImageSpec& spec, const float* pixels, EnvironmentImage& env,
                           std::string& error, long long* replaced = nullptr);

} // namespace dhdr
