#include "light_options.h"

#include "tool.h"

#include <algorithm>
#include <chrono>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/lights/emissive_lights.h>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr::app {

void addLightOptions(CommandLine& cl, LightOptions& o) {
    cl.option("--lights", "FILE",
              "lights file (JSON, docs/lights.md); repeat to add the lights of several; "
              "replaces the scene's own punctual lights",
              [&o](const std::string& v, std::string&) {
                  o.files.push_back(v);
                  return true;
              });
    cl.flag("--radiometric", o.radiometric,
            "divide photometric light units (point and spot candela, directional lux) by 683 "
            "lm/W, so that lights exported by Blender light as they do in Cycles; emission "
            "and environments are unchanged");
    cl.option("--emissive-lights", o.emissive, "on|off",
              "make every emissive mesh of the scene an area light with shadow rays (default "
              "on); off: their emission is seen only by the rays that meet them");
    cl.option("--diffuse", o.diffuse, "lambert|burley",
              "the diffuse layer of every surface: lambert, glTF's (default); burley, Blender "
              "3.x Principled BSDF's (Burley's, with its retro-reflection), to compare with a "
              "Cycles render; give the probes' bake the same");
    cl.namesFile("--lights", FileRole::Input);
}

DiffuseModel diffuseModel(const LightOptions& o) {
    return o.diffuse == "burley" ? DiffuseModel::Burley : DiffuseModel::Lambert;
}

std::string lightOptionsProblem(const LightOptions& o, bool scene) {
    if (o.emissive != "auto" && o.emissive != "on" && o.emissive != "off")
        return "--emissive-lights must be on or off";
    if (!scene && o.emissive != "auto") return "--emissive-lights needs --scene";
    if (o.diffuse != "lambert" && o.diffuse != "burley")
        return "--diffuse must be lambert or burley";
    return "";
}

std::vector<Light> sceneLights(const Scene& scene, const LightOptions& o) {
    return sceneLightList(scene, o.files.empty(), o.emissive != "off", o.radiometric);
}

std::vector<Light> sceneLights(const Tool& tool, const Scene& scene, const std::string& path,
                               const LightOptions& o) {
    size_t glowing = 0;
    std::vector<Light> lights =
        sceneLightList(scene, o.files.empty(), o.emissive != "off", o.radiometric, &glowing);
    if (o.emissive != "off")
        tool.info(path + ": " + std::to_string(glowing) + " emissive mesh" +
                  (glowing == 1 ? "" : "es") + " as area lights");
    return lights;
}

bool addLightsFiles(const Tool& tool, const std::vector<std::string>& files, const LightOptions& o,
                    std::vector<Light>& lights) {
    for (const std::string& file : files) {
        std::vector<Light> more;
        std::string error;
        std::vector<std::string> warnings;
        const auto t = std::chrono::steady_clock::now();
        if (!readLightsFile(file, more, error, warnings)) {
            tool.fail(error);
            return false;
        }
        for (const std::string& warning : warnings)
            tool.warn(warning);
        const auto environment = [](const Light& l) { return l.type == LightType::Environment; };
        const bool raw = std::any_of(more.begin(), more.end(), [&](const Light& l) {
            return environment(l) && l.ibl && l.ibl->bakedOnLoading;
        });
        if (std::any_of(more.begin(), more.end(), environment))
            tool.info(file + ": read with its environment images in " +
                      std::to_string(int(std::chrono::duration<double, std::milli>(
                                             std::chrono::steady_clock::now() - t)
                                             .count())) +
                      (raw ? " ms (a raw image is baked on reading; dhdr-ibl bakes it once)"
                           : " ms (baked by dhdr-ibl)"));
        if (o.radiometric) toRadiometricUnits(more);
        lights.insert(lights.end(), more.begin(), more.end());
    }
    return true;
}

} // namespace dhdr::app
