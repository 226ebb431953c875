// Lights in the units of glTF KHR_lights_punctual, and the lights file (docs/lights.md).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace dhdr {

// Mesh: an emissive surface of the scene made a light (emissive_lights.h); it has no entry in
// lights files.
// Environment: an equirectangular HDR image of the light arriving from every direction (ibl.h).
enum class LightType { Point, Spot, Directional, Ambient, Sphere, Rectangle, Mesh, Environment };

struct Ibl;

// The triangles of an emissive mesh in world space, 3 vertices each; they emit from both
// faces, as Blender's Emission shader does.
struct EmitterMesh {
    std::vector<glm::vec3> vertices;
    // Running sum of the triangles' areas (m²): cdf.back() is the total area.
    std::vector<float> cdf;

    size_t triangles() const { return cdf.size(); }
    float area() const { return cdf.empty() ? 0.0f : cdf.back(); }
};

struct Light {
    LightType type = LightType::Point;
    std::string name;
    glm::vec3 color{1.0f}; // linear RGB, multiplies intensity
    // Point, spot and sphere: candela (lm/sr). Rectangle: candela along its normal (a
    // Lambertian emitter, I·cos θ off the normal). Directional: lux (lm/m²). Ambient: nit
    // (cd/m²), the radiance arriving uniformly from every direction.
    float intensity = 1.0f;
    glm::vec3 position{0.0f}; // point, spot; the centre of a sphere or rectangle
    // Spot, directional: where the light travels. Rectangle: its normal, the side it emits
    // to. Unit length.
    glm::vec3 direction{0.0f, 0.0f, -1.0f};
    // Local lights: distance from `position` at which the light's smooth window reaches
    // exactly zero.
    float range = std::numeric_limits<float>::infinity();
    float radius = 0.0f; // sphere
    // Directional: the angular diameter of the sun's disk, radians, [0, π) (Blender's Sun
    // "Angle"); 0 is a point at infinity with hard shadows, more softens them.
    float angle = 0.0f;
    // Rectangle: extent along `up` (height) and along up × direction (width); `up` is unit
    // and perpendicular to `direction`.
    float width = 0.0f, height = 0.0f;
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    // Spot: angles from the axis, radians; full intensity inside the inner cone.
    float innerConeAngle = 0.0f;
    float outerConeAngle = 0.7853982f; // π/4, glTF's default
    // Mesh: the emitting triangles; `color` × `intensity` is their radiance (nit), `position`
    // the centre of their bounding sphere, whose radius is `radius`.
    std::shared_ptr<const EmitterMesh> mesh;
    // Environment: the image as the lights file names it, resolved against the file's folder;
    // its turn about +Y (radians, counter-clockwise seen from above); and its bake.
    std::string image;
    float rotation = 0.0f;
    std::shared_ptr<const Ibl> ibl;
    // Environment: the luminance above which the image's texels are split off as its sun, a
    // directional light of its own (sun.h); 0 never; negative: the default
    // (kDefaultSunThreshold for an image baked when loaded, the bake's own for a dhdr-ibl file).
    float sunThreshold = -1.0f;
    // Directional: a sun split off an environment (its intensity is the image's, not lux).
    bool environmentSun = false;

    // A light with a position, bounded by its range (all but directional and ambient).
    bool isLocal() const {
        return type != LightType::Directional && type != LightType::Ambient &&
               type != LightType::Environment;
    }
    // A light with an extent, shaded from its exact irradiance and soft-shadowed by samples.
    bool isArea() const {
        return type == LightType::Sphere || type == LightType::Rectangle || type == LightType::Mesh;
    }
};

// What the passes ask of a light, so that only the lights layer switches on its type.
inline bool isEnvironment(const Light& l) {
    return l.type == LightType::Environment;
}
inline bool isAmbient(const Light& l) {
    return l.type == LightType::Ambient;
}
inline bool isEmissiveMesh(const Light& l) {
    return l.type == LightType::Mesh;
}
// A directional light with a sun's disk (angle > 0): soft shadows, and rays can meet it.
inline bool hasSunDisk(const Light& l) {
    return l.type == LightType::Directional && l.angle > 0.0f;
}
// Light from the whole sphere of directions (USD's dome lights): environment and ambient.
inline bool isDomeLight(const Light& l) {
    return isEnvironment(l) || isAmbient(l);
}
// No position (directional, ambient, environment): what a ray that leaves the scene can meet.
inline bool isInfinite(const Light& l) {
    return !l.isLocal();
}

// The indices of the infinite lights of `lights`, in order: listed once where the lighting is
// set up, so that the passes look there for the sky instead of scanning every light (pbrt-v4's
// infiniteLights).
inline std::vector<std::uint32_t> infiniteLights(const std::vector<Light>& lights) {
    std::vector<std::uint32_t> infinite;
    for (std::uint32_t i = 0; i < lights.size(); ++i)
        if (isInfinite(lights[i])) infinite.push_back(i);
    return infinite;
}

// "point", "spot", … as the lights file names the type.
const char* lightTypeName(LightType type);

// Parses the JSON text of a lights file. On failure returns false with `error` naming the
// light's index and field (`light 3: "range" must be a positive number`).
bool parseLights(const std::string& json, std::vector<Light>& lights, std::string& error);

// Reads and parses a lights file; errors name the file. Environment images are read (relative
// to the file's folder) and baked, or read as baked (ibl.h); what was repaired in them (NaN
// texels) is added to `warnings`.
bool readLightsFile(const std::string& path, std::vector<Light>& lights, std::string& error,
                    std::vector<std::string>& warnings);

// What readLightsFile does after parsing: the images of the environment lights among `lights`
// read (relative to `folder` unless absolute; "" is the working directory) and baked, or read
// as baked, each image once; then each environment's sun added as a directional light after
// the lights. False with `error` naming the light and the image (without a file); NaN texels
// repaired are added to `warnings`. Lights parsed from text (parseLights) need it before use.
bool loadEnvironmentImages(std::vector<Light>& lights, const std::string& folder,
                           std::string& error, std::vector<std::string>& warnings);

// Blender's glTF exporter writes point and spot intensities in candela and directional ones in
// lux (photometric, W × 683 / 4π); Cycles lights with watts. Divides those three types'
// intensities by 683 lm/W, so that such lights light as in Cycles (docs/interop.md); area,
// emissive and environment lights are radiometric already and unchanged.
inline constexpr float kLuminousEfficacy = 683.0f;
void toRadiometricUnits(std::vector<Light>& lights);

// The directional light of an environment light's sun (environment.ibl->sun, found): its
// direction turned as the environment is, its illuminance in the light's colour × intensity,
// its angle; named "NAME sun".
Light environmentSunLight(const Light& environment);

// The lights file text for `lights` (what dhdr-gbuffer --lights-out writes); emissive meshes
// are left out.
std::string formatLights(const std::vector<Light>& lights);

} // namespace dhdr
