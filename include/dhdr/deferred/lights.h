// Lights in the units of glTF KHR_lights_punctual, and the lights file (docs/lights.md).
#pragma once

#include <glm/glm.hpp>

#include <limits>
#include <string>
#include <vector>

namespace dhdr {

enum class LightType { Point, Spot, Directional, Ambient };

struct Light {
    LightType type = LightType::Point;
    std::string name;
    glm::vec3 color{1.0f}; // linear RGB, multiplies intensity
    // Point and spot: candela (lm/sr). Directional: lux (lm/m²). Ambient: nit (cd/m²), the
    // radiance arriving uniformly from every direction.
    float intensity = 1.0f;
    glm::vec3 position{0.0f};            // point, spot
    glm::vec3 direction{0.0f, 0.0f, -1.0f}; // spot, directional: where the light travels; unit
    // Point, spot: distance at which the light's smooth window reaches exactly zero.
    float range = std::numeric_limits<float>::infinity();
    // Spot: angles from the axis, radians; full intensity inside the inner cone.
    float innerConeAngle = 0.0f;
    float outerConeAngle = 0.7853982f; // π/4, glTF's default

    bool isLocal() const { return type == LightType::Point || type == LightType::Spot; }
};

// Parses the JSON text of a lights file. On failure returns false with `error` naming the
// light's index and field (`light 3: "range" must be a positive number`).
bool parseLights(const std::string& json, std::vector<Light>& lights, std::string& error);

// Reads and parses a lights file; errors name the file.
bool readLightsFile(const std::string& path, std::vector<Light>& lights, std::string& error);

// The lights file text for `lights` (what dhdr-gbuffer --lights-out will write).
std::string formatLights(const std::vector<Light>& lights);

} // namespace dhdr
