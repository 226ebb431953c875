#include "flat_frame.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <dhdr/deferred/denoise/denoise.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/io/sanitize.h>
#include <dhdr/io/strip_pipeline.h>
#include <dhdr/io/strip_reader.h>
#include <thread>

namespace dhdr::app {

namespace {

// How the frame is cut: strips of whole rows of tiles, with the halo of rows around each that
// the denoiser, SSAO or an environment's footprint reads.
StripPipelineParams stripPlan(const WholeFrameRun& run, const OIIO::ImageSpec& gspec, bool ssao) {
    // SSAO looks at neighbouring pixels anywhere in the frame: one strip, the whole frame.
    // The denoiser reads kDenoiseReach rows around each pixel: each strip is read with
    // that halo, and taller, so that filtering the halo again is a smaller share (its rays
    // are traced once: EstimateCarry). Without a scene no ray is traced: nothing to filter.
    const bool halo = run.params.denoise && run.inputs.scene &&
                      (run.params.environmentSamples > 0 || run.params.aoSamples > 0 ||
                       run.params.catcherBounceSamples > 0 || run.params.specularSamples > 0);
    // About 256 rows (128 without a halo), as equal as whole rows of tiles allow: a last
    // strip of a few rows would filter two halos for little (1080 rows: 4 strips of 272
    // rather than 256 × 4 and 56). 512 rows took as long at 1080p, in 1.46× the memory
    // (bench/README.md, session 18).
    const int target = halo ? 256 : 128;
    const int count = std::max(1, (gspec.height + target * 9 / 8 - 1) / (target * 9 / 8));
    const int each = (gspec.height + count - 1) / count;
    const int rows = ssao ? gspec.height
                          : run.params.tileSize *
                                std::max(1, (each + run.params.tileSize - 1) / run.params.tileSize);
    StripPipelineParams streaming;
    streaming.rows = rows;
    // An environment's specular light reads the next row's normals (the pixel's
    // footprint, lighting.h): one row at least.
    const bool environment =
        std::any_of(run.inputs.lights.begin(), run.inputs.lights.end(), isEnvironment);
    streaming.halo = ssao ? 0 : halo ? kDenoiseReach : (environment ? kFootprintReach : 0);
    return streaming;
}

// The -v report of a lit frame: the lights considered and the rays traced.
void reportStats(const Tool& tool, const WholeFrameRun& run, const LightingStats& stats,
                 double shadeMs) {
    const double pixels = double(std::max<long long>(stats.coveredPixels, 1));
    char line[200];
    std::snprintf(line, sizeof line,
                  "%zu lights; %lld covered pixels; per covered pixel %.2f considered, %.2f "
                  "within range%s; %lld tile-list entries",
                  run.inputs.lights.size(), stats.coveredPixels,
                  double(stats.lightEvaluations) / pixels, double(stats.lightsReaching) / pixels,
                  run.params.bruteForce ? " (brute force)" : "", stats.tileListEntries);
    tool.info(line);
    const long long traced =
        stats.shadowRays + stats.aoRays + stats.bounceRays + stats.pathRays + stats.specularRays;
    if (traced > 0) {
        const double seconds = std::max(shadeMs, 1e-3) / 1000.0;
        std::snprintf(
            line, sizeof line,
            "%lld shadow rays (%.2f per covered pixel), %lld AO rays, %lld catcher bounce "
            "rays, %lld specular rays, %lld path rays; %.2f M rays/s per thread over the "
            "shading time",
            stats.shadowRays, double(stats.shadowRays) / pixels, stats.aoRays, stats.bounceRays,
            stats.specularRays, stats.pathRays,
            double(traced) / seconds / 1e6 /
                double(tool.threads() > 0 ? tool.threads()
                                          : int(std::thread::hardware_concurrency())));
        tool.info(line);
    }
}

} // namespace

bool lightFlatGBuffer(const WholeFrameRun& run, const SsaoParams* ssao, const std::string& path,
                      int part, const std::string& out, const std::string& lightFiles) {
    const Tool& tool = run.tool;
    const auto start = std::chrono::steady_clock::now();
    std::string error;
    StripReader reader;
    if (!reader.open(path, part, 0, 1 << 20, tool.threads(), error)) {
        tool.fail(cannotRead(path, error));
        return false;
    }
    const OIIO::ImageSpec& gspec = reader.spec();
    gbuffer::Layout layout;
    std::string missing;
    if (!gbuffer::findLayout(gspec, layout, missing)) {
        tool.fail(path + ": no channel '" + missing + "' — is this a G-buffer?");
        return false;
    }
    if (!run.prepareFrame(path, gspec)) return false;
    // Strip by strip, whole rows of tiles at a time: memory stays at one strip of the
    // G-buffer and one of the output whatever the frame's size, and each pixel's result
    // is the same as from the whole frame (tiles are laid over the frame).
    LightingParams strips = run.params;
    strips.frame = OIIO::get_roi(gspec);
    AtomicOutput file(tool, out);
    LightingStats stats;
    Progress progress(tool, "dhdr-light: " + path);
    // The next strip is read on another thread while this one is shaded and written:
    // decoding the G-buffer is most of the work.
    StripPipelineParams streaming = stripPlan(run, gspec, ssao != nullptr);
    streaming.nthreads = tool.threads();
    streaming.progress = progress.over();
    // The strips' shared rows are decoded once (the shading only reads its G-buffer).
    streaming.shareHalo = true;
    StripPipeline pipeline(OIIO::get_roi(gspec), streaming);
    // Z is +∞ on the background by contract; every other channel must be finite.
    StripInput gbufferRows{[&](int y0, int y1, OIIO::ImageBuf& s, std::string& e) {
                               return reader.read(y0, y1, s, e);
                           },
                           path,
                           {{0, layout.depth}, {layout.depth + 1, gspec.nchannels}}};
    gbufferRows.readReusing = [&](int y0, int y1, const OIIO::ImageBuf& previous, OIIO::ImageBuf& s,
                                  int& copiedEnd, std::string& e) {
        return reader.read(y0, y1, s, e, &previous, &copiedEnd);
    };
    pipeline.addInput(std::move(gbufferRows));
    const OIIO::TypeDesc type = run.outputType;
    pipeline.setOutput(file.file(), [&](const OIIO::ImageBuf& first, std::string& e) {
        if (file.file().open(litFrameSpec(first.spec(), gspec, lightFiles), {type})) return true;
        e = file.file().geterror();
        return false;
    });
    OIIO::ImageBuf ao;
    // The estimates of the rows two strips share are traced once, by the upper strip.
    EstimateCarry carry;
    const bool lit = pipeline.run([&](StripContext& strip) {
        const OIIO::ImageBuf& gbuf = *strip.inputs[0];
        LightingInputs stripInputs = run.inputs;
        stripInputs.carry = &carry;
        if (ssao) {
            if (!screenSpaceAO(ao, gbuf, *ssao, tool.threads())) {
                strip.error = path + ": " + ao.geterror();
                return false;
            }
            stripInputs.ambientOcclusion = &ao;
        }
        // The frame's pixels before this strip's, and the strip's as they are shaded.
        const long long framePixels = (long long)gspec.width * gspec.height,
                        before = (long long)(strip.rows.ybegin - gspec.y) * gspec.width;
        const std::function<void(long long, long long)> shaded = [&](long long done, long long) {
            progress.update(float(double(before + done) / double(framePixels)), before + done,
                            framePixels, "pixels");
        };
        stripInputs.shaded = &shaded;
        LightingStats rowStats;
        const OIIO::ROI own(gspec.x, gspec.x + gspec.width, strip.rows.ybegin, strip.rows.yend);
        if (!shadeGBuffer(*strip.output, gbuf, stripInputs, strips, own, tool.threads(),
                          &rowStats)) {
            strip.error = path + ": " + strip.output->geterror();
            return false;
        }
        stats += rowStats;
        return true;
    });
    if (!lit) {
        tool.fail(pipeline.error());
        return false;
    }
    const NonFiniteCount replaced = pipeline.replaced()[0];
    const double readMs = pipeline.readMs(), shadeMs = pipeline.processMs(),
                 writeMs = pipeline.writeMs();
    if (!file.commit()) return false;
    tool.reportNonFinite(path, replaced, false);
    warnAboutSurfaces(tool, path, stats);
    reportStats(tool, run, stats, shadeMs);
    auto ms = [](double v) { return std::to_string(int(v + 0.5)) + " ms"; };
    tool.info("total " +
              ms(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                     .count()) +
              ": read " + ms(readMs) + ", shade " + ms(shadeMs) + ", write " + ms(writeMs) +
              (reader.streamed() ? "" : " (read whole: not a scanline EXR)"));
    return true;
}

} // namespace dhdr::app
