// The options every tool that reads lights takes (dhdr-light, dhdr-probes), with one help
// text and one order of the lights they give, so that a lights file and a scene mean the same
// to both: a probe ray's hit is lit by the lights, in the order and with the seeds, that the
// frame's pixels are.
#pragma once

#include "command_line.h"

#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/scene/lights.h>
#include <string>
#include <vector>

namespace dhdr {
struct Scene;
}

namespace dhdr::app {

class Tool;

struct LightOptions {
    std::vector<std::string> files; // --lights, in the order given
    // --radiometric: the lights' intensities are photometric (Blender's glTF export) and are
    // divided by 683 lm/W (dhdr::toRadiometricUnits).
    bool radiometric = false;
    std::string emissive = "auto";   // --emissive-lights on|off; auto: on (with a scene)
    std::string diffuse = "lambert"; // --diffuse lambert|burley: every surface's diffuse layer
};

void addLightOptions(CommandLine& cl, LightOptions& options);

// A usage error in the options ("" if none); `scene` whether the tool has one.
std::string lightOptionsProblem(const LightOptions& options, bool scene);

// --diffuse as the library's model (after lightOptionsProblem said it is one).
DiffuseModel diffuseModel(const LightOptions& options);

// The scene's lights as every tool orders them: its own punctual lights unless lights files
// are given, then its emissive meshes as area lights (unless --emissive-lights off), in
// radiometric units with --radiometric.
std::vector<Light> sceneLights(const Tool& tool, const Scene& scene, const std::string& path,
                               const LightOptions& options);
// The same without a word (a scene posed again for another frame).
std::vector<Light> sceneLights(const Scene& scene, const LightOptions& options);

// Appends the lights of `files` in order (their warnings as the tool's), in radiometric units
// with --radiometric. False (after the tool's error) when a file cannot be read.
bool addLightsFiles(const Tool& tool, const std::vector<std::string>& files,
                    const LightOptions& options, std::vector<Light>& lights);

} // namespace dhdr::app
