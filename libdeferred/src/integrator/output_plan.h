// The lighting pass's output plan (as Cycles plans its passes, scene/pass.cpp): which
// channels follow R, G, B, A and where — AO, then the probes' indirect light, then the specular
// indirect light, then the G-buffer channels passed through.
#pragma once

#include "integrator/shade_setup.h"

#include <OpenImageIO/imagebuf.h>
#include <dhdr/deferred/gbuffer/shading_point.h>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace dhdr {

struct OutputPlan {
    bool ao = false, indirect = false, specular = false; // the AOVs written
    int indirectAt = 0, specularAt = 0;                  // their first channels, counted after A
    int aovs = 0; // AOV channels after A; the channels passed through next
    std::vector<std::string> passNames;
    std::vector<int> passIndex; // their channels in the G-buffer

    // The output's header: `in`'s metadata, the pixels of `roi`, the channels planned, float.
    OIIO::ImageSpec spec(const OIIO::ImageSpec& in, OIIO::ROI roi) const;
    // A sample's AOVs (`out` points after A): its AO, the probes' light and the traced
    // specular light.
    void write(float* out, float occlusion, const glm::vec3& indirectLight,
               const glm::vec3& reflected) const;
    // The AOVs where nothing of theirs is computed: AO 1, no indirect light.
    void writeNone(float* out) const;
    // The channels passed through of pixel (x, y), which holds `samples` samples.
    void passThrough(float* out, const GBufferView& view, int x, int y, int samples) const;
};

// The indices of the channels `names` in `in`; false with `missing` naming one it lacks.
bool findPassThrough(const OIIO::ImageSpec& in, const std::vector<std::string>& names,
                     std::vector<int>& index, std::string& missing);

// The AOVs params asks for that the setup computes, and the channels passed through (their
// indices from findPassThrough).
OutputPlan planOutput(const LightingParams& params, const ShadeSetup& setup,
                      std::vector<int> passIndex);

// `dst` with header `spec`: reused when it already holds float pixels of that size and those
// channels (the previous strip), else reset (pixels not initialized).
void prepareOutput(OIIO::ImageBuf& dst, const OIIO::ImageSpec& spec);

} // namespace dhdr
