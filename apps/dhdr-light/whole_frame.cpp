#include "whole_frame.h"

#include <OpenImageIO/deepdata.h>
#include <chrono>
#include <cstdio>
#include <dhdr/deferred/deep_gbuffer.h>
#include <dhdr/tonemap/sanitize.h>

namespace dhdr::app {

namespace {

double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

std::string ms(double v) {
    return std::to_string(int(v + 0.5)) + " ms";
}

// dhdr-light's output of a frame lit whole: its pixels, the lights files named in the header.
bool writeLitFrame(const WholeFrameRun& run, OIIO::ImageSpec spec, const OIIO::ImageBuf& hdr,
                   const std::string& out) {
    AtomicOutput file(run.tool, out);
    return file.open(spec, {run.outputType}) &&
           file.writeRows(spec.y, spec.y + spec.height,
                          static_cast<const float*>(hdr.localpixels())) &&
           file.commit();
}

// The lit samples as a deep RGBA EXR: premultiplied, with the G-buffer's depths, in its order.
bool writeLitSamples(const WholeFrameRun& run, const DeepGBuffer& gbuf,
                     const std::vector<float>& sampleRGBA, const OIIO::ImageSpec& spec,
                     const std::string& path) {
    const OIIO::ImageSpec& gspec = gbuf.spec;
    DeepGBuffer lit;
    lit.spec = spec;
    lit.spec.nchannels = 6;
    lit.spec.channelnames = {"R", "G", "B", "A", "Z", "ZBack"};
    lit.spec.alpha_channel = 3;
    lit.spec.z_channel = 4;
    lit.first = gbuf.first;
    lit.values.resize(gbuf.totalSamples() * 6);
    for (size_t k = 0; k < gbuf.totalSamples(); ++k) {
        for (int c = 0; c < 4; ++c)
            lit.values[6 * k + size_t(c)] = sampleRGBA[4 * k + size_t(c)];
        lit.values[6 * k + 4] = gbuf.values[k * size_t(gspec.nchannels) + 1];
        lit.values[6 * k + 5] = gbuf.values[k * size_t(gspec.nchannels) + 2];
    }
    const std::vector<OIIO::TypeDesc> formats = {run.outputType,        run.outputType,
                                                 run.outputType,        run.outputType,
                                                 OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::FLOAT};
    OIIO::ImageSpec deepSpec = lit.spec;
    deepSpec.channelformats = formats;
    OIIO::DeepData data;
    toDeepData(lit, gspec.y, gspec.y + gspec.height, data, formats);
    AtomicOutput file(run.tool, path);
    return file.openDeep(deepSpec) && file.writeDeepRows(gspec.y, gspec.y + gspec.height, data) &&
           file.commit();
}

} // namespace

bool lightDeepGBuffer(const WholeFrameRun& run, const std::string& path, int part,
                      const std::string& out, const std::string& lightFiles,
                      const std::string& deepOut) {
    const Tool& tool = run.tool;
    const auto start = std::chrono::steady_clock::now();
    DeepGBuffer gbuf;
    std::string error;
    long long replaced = 0;
    if (!readDeepGBuffer(path, part, gbuf, error, &replaced)) {
        tool.fail(path + ": " + error);
        return false;
    }
    NonFiniteCount counted;
    counted.nan = replaced;
    tool.reportNonFinite(path, counted, false);
    if (!run.prepareFrame(path, gbuf.spec)) return false;
    const double readMs = msSince(start);
    auto t = std::chrono::steady_clock::now();
    OIIO::ImageBuf hdr;
    LightingStats stats;
    std::vector<float> sampleRGBA;
    if (!shadeGBuffer(hdr, gbuf, run.inputs, run.params, {}, tool.threads(), &stats,
                      deepOut.empty() ? nullptr : &sampleRGBA)) {
        tool.fail(path + ": " + hdr.geterror());
        return false;
    }
    const double shadeMs = msSince(t);
    t = std::chrono::steady_clock::now();
    OIIO::ImageSpec spec = hdr.spec();
    spec.attribute("dhdr:lights", lightFiles);
    spec.erase_attribute("dhdr:materialNames");
    spec.erase_attribute("dhdr:objectNames");
    if (!deepOut.empty() && !writeLitSamples(run, gbuf, sampleRGBA, spec, deepOut)) return false;
    if (!writeLitFrame(run, spec, hdr, out)) return false;
    const double writeMs = msSince(t);
    if (stats.coveredPixels == 0)
        tool.warn(path + ": no surface in view: A is 0 everywhere (an empty frame)");
    char line[200];
    std::snprintf(line, sizeof line,
                  "deep: %zu samples over %lld covered pixels; %lld shadow rays, %lld AO rays",
                  gbuf.totalSamples(), stats.coveredPixels, stats.shadowRays, stats.aoRays);
    tool.info(line);
    tool.info("total " + ms(msSince(start)) + ": read " + ms(readMs) + ", shade " + ms(shadeMs) +
              ", write " + ms(writeMs));
    return true;
}

bool lightMappedPasses(const WholeFrameRun& run, const ChannelMap& map,
                       const std::optional<Camera>& camera, const std::string& path,
                       const std::string& out, const std::string& lightFiles) {
    const Tool& tool = run.tool;
    const auto start = std::chrono::steady_clock::now();
    OIIO::ImageBuf src(path);
    if (!src.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
        tool.fail(path + ": cannot read: " + src.geterror());
        return false;
    }
    OIIO::ImageBuf gbuf;
    std::vector<std::string> warnings;
    std::string error;
    if (!importGBuffer(src, map, gbuf, warnings, error)) {
        tool.fail(path + ": " + error);
        return false;
    }
    for (const std::string& w : warnings)
        tool.warn(path + ": " + w);
    OIIO::ImageSpec& spec = gbuf.specmod();
    if (camera) {
        gbuffer::CameraInfo info;
        info.worldToCamera = camera->worldToCamera();
        info.worldToNDC = camera->worldToNDC(double(spec.width) / spec.height);
        gbuffer::writeCamera(spec, info);
    }
    if (!run.prepareFrame(path, spec)) return false;
    OIIO::ImageBuf hdr;
    LightingStats stats;
    if (!shadeGBuffer(hdr, gbuf, run.inputs, run.params, {}, tool.threads(), &stats)) {
        tool.fail(path + ": " + hdr.geterror());
        return false;
    }
    OIIO::ImageSpec outSpec = hdr.spec();
    outSpec.attribute("dhdr:lights", lightFiles);
    outSpec.attribute("dhdr:channelMap", map.name);
    if (!writeLitFrame(run, outSpec, hdr, out)) return false;
    tool.info(path + ": read through the channel map " + map.name + "; " +
              std::to_string(stats.coveredPixels) + " covered pixels, " + ms(msSince(start)));
    return true;
}

} // namespace dhdr::app
