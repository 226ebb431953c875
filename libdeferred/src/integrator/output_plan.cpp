#include "integrator/output_plan.h"

#include <algorithm>

namespace dhdr {

bool findPassThrough(const OIIO::ImageSpec& in, const std::vector<std::string>& names,
                     std::vector<int>& index, std::string& missing) {
    for (const std::string& name : names) {
        const int c = in.channelindex(name);
        if (c < 0) {
            missing = name;
            return false;
        }
        index.push_back(c);
    }
    return true;
}

OutputPlan planOutput(const LightingParams& params, const ShadeSetup& setup,
                      std::vector<int> passIndex) {
    OutputPlan plan;
    plan.ao = params.writeAO;
    plan.indirect = params.writeIndirect && setup.probes;
    plan.specular = params.writeSpecular && setup.specularActive;
    plan.indirectAt = plan.ao ? 1 : 0;
    plan.specularAt = plan.indirectAt + (plan.indirect ? 3 : 0);
    plan.aovs = plan.specularAt + (plan.specular ? 3 : 0);
    plan.passNames = params.passThrough;
    plan.passIndex = std::move(passIndex);
    return plan;
}

OIIO::ImageSpec OutputPlan::spec(const OIIO::ImageSpec& in, OIIO::ROI roi) const {
    OIIO::ImageSpec spec = in;
    spec.x = roi.xbegin;
    spec.y = roi.ybegin;
    spec.width = roi.width();
    spec.height = roi.height();
    spec.nchannels = 4 + aovs + int(passIndex.size());
    spec.channelnames = {"R", "G", "B", "A"};
    if (ao) spec.channelnames.push_back("AO");
    if (indirect)
        spec.channelnames.insert(spec.channelnames.end(),
                                 {"indirect.R", "indirect.G", "indirect.B"});
    if (specular)
        spec.channelnames.insert(spec.channelnames.end(),
                                 {"specular.R", "specular.G", "specular.B"});
    for (const std::string& name : passNames)
        spec.channelnames.push_back(name);
    spec.alpha_channel = 3;
    spec.z_channel = spec.channelindex("Z");
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.channelformats.clear();
    return spec;
}

void OutputPlan::write(float* out, float occlusion, const glm::vec3& indirectLight,
                       const glm::vec3& reflected) const {
    if (ao) out[0] = occlusion;
    if (indirect)
        for (int c = 0; c < 3; ++c)
            out[indirectAt + c] = indirectLight[c];
    if (specular)
        for (int c = 0; c < 3; ++c)
            out[specularAt + c] = reflected[c];
}

void OutputPlan::writeNone(float* out) const {
    if (ao) out[0] = 1.0f;
    if (indirect) std::fill(out + indirectAt, out + indirectAt + 3, 0.0f);
    if (specular) std::fill(out + specularAt, out + specularAt + 3, 0.0f);
}

void OutputPlan::passThrough(float* out, const GBufferView& view, int x, int y, int samples) const {
    for (size_t k = 0; k < passIndex.size(); ++k)
        out[4 + aovs + k] = samples > 0 || !view.deep() ? view.channels(x, y)[passIndex[k]] : 0.0f;
}

void prepareOutput(OIIO::ImageBuf& dst, const OIIO::ImageSpec& spec) {
    const OIIO::ImageSpec& held = dst.spec();
    if (dst.initialized() && dst.localpixels() && held.format == OIIO::TypeDesc::FLOAT &&
        held.channelformats.empty() && held.nchannels == spec.nchannels &&
        held.width == spec.width && held.height == spec.height) {
        dst.specmod() = spec;
    } else {
        dst.reset(spec, OIIO::InitializePixels::No);
    }
}

} // namespace dhdr
