// dhdr-light's G-buffers that are not flat G-buffers of the contract: deep G-buffers (read and
// lit a band of rows at a time, as deep data) and other renderers' passes read whole through a
// channel map.
#pragma once

#include "../common/tool.h"

#include <dhdr/deferred/gbuffer/gbuffer_import.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/scene/camera.h>
#include <functional>
#include <optional>
#include <string>

namespace dhdr::app {

// What these paths need of the run: its tool, lights and parameters, the output's pixel type,
// and the checks every G-buffer passes before shading (camera, plate, scene).
struct WholeFrameRun {
    const Tool& tool;
    const LightingInputs& inputs;
    const LightingParams& params;
    OIIO::TypeDesc outputType;
    std::function<bool(const std::string& path, const OIIO::ImageSpec& gbuffer)> prepareFrame;
};

// The header of dhdr-light's output, from the first lit strip's: the frame's rows (those of
// `gbuffer`), the lights files named, the G-buffer's name tables left out.
OIIO::ImageSpec litFrameSpec(const OIIO::ImageSpec& strip, const OIIO::ImageSpec& gbuffer,
                             const std::string& lightFiles);

// What the shading of `path` found of its surfaces: none in view, or normals that were no
// direction and were replaced.
void warnAboutSurfaces(const Tool& tool, const std::string& path, const LightingStats& stats);

// A deep G-buffer: every sample lit and composited into `out`; with `deepOut`, the lit samples
// as a deep RGBA EXR too. `lightFiles` is recorded in the output's header.
bool lightDeepGBuffer(const WholeFrameRun& run, const std::string& path, int part,
                      const std::string& out, const std::string& lightFiles,
                      const std::string& deepOut);

// Another renderer's passes at `path`, mapped to the contract by `map`; the camera from
// `camera`, else from the file's own matrices.
bool lightMappedPasses(const WholeFrameRun& run, const ChannelMap& map,
                       const std::optional<Camera>& camera, const std::string& path,
                       const std::string& out, const std::string& lightFiles);

} // namespace dhdr::app
