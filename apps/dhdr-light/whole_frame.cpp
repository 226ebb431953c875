#include "whole_frame.h"

#include <OpenImageIO/deepdata.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <dhdr/deferred/denoise/denoise_inputs.h>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/io/sanitize.h>
#include <dhdr/io/strip_pipeline.h>
#include <optional>
#include <utility>

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

// The lit samples of rows [ybegin, yend) of a band as deep RGBA rows: premultiplied, with the
// G-buffer's depths, in its order.
OIIO::DeepData litSamples(const DeepGBuffer& gbuf, const std::vector<float>& sampleRGBA,
                          const std::vector<OIIO::TypeDesc>& formats, int ybegin, int yend) {
    const OIIO::ImageSpec& gspec = gbuf.spec;
    DeepGBuffer lit;
    lit.spec = gspec;
    lit.spec.nchannels = 6;
    lit.spec.channelnames = {"R", "G", "B", "A", "Z", "ZBack"};
    lit.first = gbuf.first;
    lit.values.resize(gbuf.totalSamples() * 6);
    for (size_t k = 0; k < gbuf.totalSamples(); ++k) {
        for (int c = 0; c < 4; ++c)
            lit.values[6 * k + size_t(c)] = sampleRGBA[4 * k + size_t(c)];
        lit.values[6 * k + 4] = gbuf.values[k * size_t(gspec.nchannels) + 1];
        lit.values[6 * k + 5] = gbuf.values[k * size_t(gspec.nchannels) + 2];
    }
    OIIO::DeepData data;
    toDeepData(lit, ybegin, yend, data, formats);
    return data;
}

// The rows of the frame the denoiser reads around a band's (lighting_params.h): none when
// nothing is traced to filter.
int denoiseHalo(const WholeFrameRun& run) {
    const LightingParams& p = run.params;
    const bool traced = p.environmentSamples > 0 || p.aoSamples > 0 || p.catcherBounceSamples > 0 ||
                        p.specularSamples > 0;
    return p.denoise && !p.pathTrace && run.inputs.scene && traced ? kDenoiseReach : 0;
}

// Rows `rows` of the frame and `halo` rows above and below them (within the frame) into
// `band`; the non-finite values replaced are counted in `rows` only (the halo rows are
// another band's, and counted there).
bool readBand(DeepGBufferReader& reader, OIIO::ROI rows, int halo, DeepGBuffer& band,
              std::string& error, long long* replaced) {
    const OIIO::ImageSpec& frame = reader.spec();
    const int y0 = std::max(frame.y, rows.ybegin - halo),
              y1 = std::min(frame.y + frame.height, rows.yend + halo);
    if (y0 == rows.ybegin && y1 == rows.yend)
        return reader.read(rows.ybegin, rows.yend, band, error, replaced);
    DeepGBuffer part;
    band = DeepGBuffer();
    for (const auto& [begin, end] : {std::pair{y0, rows.ybegin}, std::pair{rows.ybegin, rows.yend},
                                     std::pair{rows.yend, y1}}) {
        if (begin == end) continue;
        if (!reader.read(begin, end, part, error, begin == rows.ybegin ? replaced : nullptr))
            return false;
        if (band.first.empty()) {
            band = std::move(part);
            continue;
        }
        const std::uint32_t offset = band.first.back();
        band.first.pop_back();
        for (const std::uint32_t f : part.first)
            band.first.push_back(offset + f);
        band.values.insert(band.values.end(), part.values.begin(), part.values.end());
        band.spec.height += part.spec.height;
    }
    return true;
}

} // namespace

void warnAboutSurfaces(const Tool& tool, const std::string& path, const LightingStats& stats) {
    if (stats.coveredPixels == 0)
        tool.warn(path + ": no surface in view: A is 0 everywhere (an empty frame)");
    if (stats.repairedNormals > 0)
        tool.warn(path + ": " + std::to_string(stats.repairedNormals) +
                  " surface samples with a normal of zero length (or NaN or infinite) were shaded "
                  "with the geometric normal Ng, or facing the camera without one");
}

OIIO::ImageSpec litFrameSpec(const OIIO::ImageSpec& strip, const OIIO::ImageSpec& gbuffer,
                             const std::string& lightFiles) {
    OIIO::ImageSpec spec = strip;
    spec.y = gbuffer.y;
    spec.height = gbuffer.height;
    spec.attribute("dhdr:lights", lightFiles);
    spec.erase_attribute("dhdr:materialNames");
    spec.erase_attribute("dhdr:objectNames");
    return spec;
}

bool lightDeepGBuffer(const WholeFrameRun& run, const std::string& path, int part,
                      const std::string& out, const std::string& lightFiles,
                      const std::string& deepOut) {
    const Tool& tool = run.tool;
    const auto start = std::chrono::steady_clock::now();
    DeepGBufferReader reader;
    std::string error;
    if (!reader.open(path, part, error)) {
        tool.fail(path + ": " + error);
        return false;
    }
    const OIIO::ImageSpec& frame = reader.spec();
    if (const std::string e = pixelLimitError(frame.width, frame.height, frame.depth); !e.empty()) {
        tool.fail(path + ": " + e);
        return false;
    }
    if (!run.prepareFrame(path, frame)) return false;
    // A band of whole rows of tiles at a time, about 256K pixels (a deep band's tables of
    // samples and pointers cost ~400 bytes a pixel), read with the denoiser's halo: memory
    // follows a band's samples, and each pixel's result is the frame's (tiles are laid over the
    // frame; the estimates the halo shares with the previous band are carried, not traced again).
    LightingParams params = run.params;
    params.frame = OIIO::get_roi(frame);
    const int tile = params.tileSize;
    const int rows =
        tile * std::clamp(262144 / std::max(1, frame.width * tile), 1, std::max(1, 128 / tile));
    AtomicOutput file(tool, out);
    std::optional<AtomicOutput> deepFile;
    if (!deepOut.empty()) deepFile.emplace(tool, deepOut);
    const std::vector<OIIO::TypeDesc> deepFormats = {run.outputType,        run.outputType,
                                                     run.outputType,        run.outputType,
                                                     OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::FLOAT};
    const int halo = denoiseHalo(run);
    LightingInputs inputs = run.inputs;
    EstimateCarry carry;
    inputs.carry = &carry;
    DeepGBuffer band;
    OIIO::ImageBuf hdr;
    LightingStats stats;
    std::vector<float> sampleRGBA;
    long long replaced = 0;
    size_t samples = 0;
    Progress progress(tool, "dhdr-light: " + path);
    // One band in memory at a time: no reading ahead, which would hold two.
    StripPipelineParams streaming;
    streaming.rows = rows;
    streaming.readAhead = false;
    streaming.progress = progress.over();
    double readMs = 0.0, shadeMs = 0.0, writeMs = 0.0;
    StripStages stages;
    stages.read = [&](OIIO::ROI r, int, std::string& e) {
        const auto t = std::chrono::steady_clock::now();
        if (!readBand(reader, r, halo, band, e, &replaced)) {
            e = path + ": " + e;
            return false;
        }
        samples +=
            band.first[band.pixel(frame.x, r.yend)] - band.first[band.pixel(frame.x, r.ybegin)];
        readMs += msSince(t);
        return true;
    };
    stages.process = [&](OIIO::ROI r, int, std::string& e) {
        const auto t = std::chrono::steady_clock::now();
        const long long framePixels = (long long)frame.width * frame.height,
                        before = (long long)(r.ybegin - frame.y) * frame.width;
        const std::function<void(long long, long long)> shaded = [&](long long done, long long) {
            progress.update(float(double(before + done) / double(framePixels)), before + done,
                            framePixels, "pixels");
        };
        inputs.shaded = &shaded;
        LightingStats bandStats;
        const bool lit = shadeGBuffer(hdr, band, inputs, params, r, tool.threads(), &bandStats,
                                      deepOut.empty() ? nullptr : &sampleRGBA);
        inputs.shaded = nullptr;
        if (!lit) {
            e = path + ": " + hdr.geterror();
            return false;
        }
        stats += bandStats;
        shadeMs += msSince(t);
        if (r.ybegin > frame.y) return true;
        const OIIO::ImageSpec spec = litFrameSpec(hdr.spec(), frame, lightFiles);
        if (!file.file().open(spec, {run.outputType})) {
            e = file.file().geterror();
            return false;
        }
        if (deepOut.empty()) return true;
        OIIO::ImageSpec deepSpec = spec;
        deepSpec.nchannels = 6;
        deepSpec.channelnames = {"R", "G", "B", "A", "Z", "ZBack"};
        deepSpec.alpha_channel = 3;
        deepSpec.z_channel = 4;
        deepSpec.channelformats = deepFormats;
        if (deepFile->file().openDeep(deepSpec)) return true;
        e = deepFile->file().geterror();
        return false;
    };
    stages.write = [&](OIIO::ROI r, int, std::string& e) {
        const auto t = std::chrono::steady_clock::now();
        if (!file.file().writeRows(hdr, r)) {
            e = file.file().geterror();
            return false;
        }
        if (!deepOut.empty() &&
            !deepFile->file().writeDeepRows(
                r.ybegin, r.yend, litSamples(band, sampleRGBA, deepFormats, r.ybegin, r.yend))) {
            e = deepFile->file().geterror();
            return false;
        }
        writeMs += msSince(t);
        return true;
    };
    if (std::string e; !runStrips(OIIO::get_roi(frame), streaming, stages, e)) {
        tool.fail(e);
        return false;
    }
    if (deepFile && !deepFile->commit()) return false;
    if (!file.commit()) return false;
    NonFiniteCount counted;
    counted.nan = replaced;
    tool.reportNonFinite(path, counted, false);
    warnAboutSurfaces(tool, path, stats);
    char line[200];
    std::snprintf(line, sizeof line,
                  "deep: %zu samples over %lld covered pixels; %lld shadow rays, %lld AO rays",
                  samples, stats.coveredPixels, stats.shadowRays, stats.aoRays);
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
    if (src.init_spec(path, 0, 0))
        if (const std::string e =
                pixelLimitError(src.spec().width, src.spec().height, src.spec().depth);
            !e.empty()) {
            tool.fail(path + ": " + e);
            return false;
        }
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
    warnAboutSurfaces(tool, path, stats);
    tool.info(path + ": read through the channel map " + map.name + "; " +
              std::to_string(stats.coveredPixels) + " covered pixels, " + ms(msSince(start)));
    return true;
}

} // namespace dhdr::app
