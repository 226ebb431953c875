// dhdr-bloom: linear HDR in, the same with bloom added out (docs/tools.md).
#include "../common/frames.h"
#include "../common/param_options.h"
#include "../common/tool.h"

#include <dhdr/io/layers.h>
#include <dhdr/io/sanitize.h>
#include <dhdr/io/strip_pipeline.h>
#include <dhdr/tonemap/bloom.h>

using namespace dhdr;

namespace {

int run(int argc, char** argv) {
    app::CommandLine cl("dhdr-bloom", "HDR.exr -o HDR.exr [options]",
                        "Bloom in HDR: a quarter-size copy, a bright pass (8-tap box, kept where "
                        "the tone-mapped\nluminance exceeds the threshold), downsampled to 1/8, a "
                        "separable Gaussian, upsampled\nbilinearly and added to R, G, B. Other "
                        "channels pass through unchanged.");
    BloomParams params;
    app::addParamOptions(cl, params, kBloomFloatTable);
    std::string layer;
    cl.option("--layer", layer, "NAME",
              "the layer or EXR part to bloom (default: the unnamed R,G,B,A, else the one "
              "called Combined, rgba or beauty)");
    cl.epilog("Example:\n  dhdr-bloom frame.hdr.exr -o frame.bloom.exr --strength 0.8");
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-bloom", cl);
    if (cl.inputs().size() != 1) {
        std::fprintf(stderr, "dhdr-bloom: usage error: give one HDR image\n");
        return app::kExitUsage;
    }
    app::FramePlan plan;
    if (const int status = app::planFrames(tool, cl.inputs(), plan); status >= 0) return status;
    return app::runFrames(tool, plan, [&](int, const auto& in, const auto& out) {
        const std::string& path = in[0];
        ColourStripReader reader;
        if (!tool.openColour(path, layer, true, reader)) return false;
        const OIIO::ImageSpec& frame = reader.spec();
        // Two passes over the frame, strip by strip (BloomBuilder): meter and reduce to the
        // quarter-size copy, then add the layer. Memory: a strip and the 1/4-size copy.
        BloomBuilder builder(OIIO::get_roi(frame), params, tool.threads());
        app::Progress progress(tool, "dhdr-bloom: " + path);
        StripPipelineParams strips;
        strips.nthreads = tool.threads();
        const StripInput input = {[&](int y0, int y1, OIIO::ImageBuf& s, std::string& e) {
                                      return reader.read(y0, y1, s, e);
                                  },
                                  path,
                                  {{0, 3}}};
        bool anySurface = false;
        strips.progress = progress.over(0.0f, 0.5f);
        StripPipeline metering(OIIO::get_roi(frame), strips);
        metering.addInput(input);
        const bool metered = metering.run([&](StripContext& strip) {
            anySurface = anySurface || app::hasSurface(*strip.inputs[0]);
            if (builder.addRows(*strip.inputs[0])) return true;
            strip.error = path + ": " + builder.error();
            return false;
        });
        if (!metered) {
            tool.fail(metering.error());
            return false;
        }
        if (!builder.finish()) {
            tool.fail(path + ": " + builder.error());
            return false;
        }
        if (!anySurface) tool.warnNoSurface(path);
        tool.reportNonFinite(path, metering.replaced()[0], false);
        OIIO::ImageSpec spec = frame;
        spec.attribute("dhdr:bloomStrength", params.strength);
        app::AtomicOutput file(tool, out);
        if (!file.open(spec, reader.formats())) return false;
        strips.progress = progress.over(0.5f, 1.0f);
        StripPipeline adding(OIIO::get_roi(frame), strips);
        adding.addInput(input);
        adding.setOutput(file.file());
        const bool added = adding.run([&](StripContext& strip) {
            // In place, the strip then handed to the writer (the next one reads into the
            // other slot).
            OIIO::ImageBuf& rows = *strip.inputs[0];
            if (!builder.apply(rows, rows)) {
                strip.error = path + ": " + rows.geterror();
                return false;
            }
            strip.output->swap(rows);
            return true;
        });
        if (!added) {
            tool.fail(adding.error());
            return false;
        }
        return file.commit();
    });
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-bloom", [&] { return run(argc, argv); });
}
