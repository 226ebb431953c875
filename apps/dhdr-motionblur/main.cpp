// dhdr-motionblur: motion blur in post, in linear HDR, from a G-buffer's motion vectors
// (docs/tools.md, docs/animation.md).
#include "../common/frames.h"
#include "../common/param_options.h"
#include "../common/tool.h"

#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <dhdr/io/errors.h>
#include <dhdr/io/layers.h>
#include <dhdr/io/motion_channels.h>
#include <dhdr/io/strip_pipeline.h>
#include <dhdr/io/strip_reader.h>
#include <dhdr/tonemap/motion_blur.h>
#include <memory>

using namespace dhdr;

namespace {

// The part of `path` that holds motion channels (a multi-part file), and its spec.
bool openGeometry(app::Tool& tool, const std::string& path, StripReader& reader,
                  MotionChannels& channels) {
    OIIO::ImageSpec spec;
    const int part = tool.findPart(
        path, [](const OIIO::ImageSpec& spec) { return findMotionChannels(spec).motion >= 0; },
        spec);
    if (part < 0) return false;
    channels = findMotionChannels(spec);
    if (channels.motion < 0) {
        tool.fail(path + ": no motion channels (motion.X motion.Y motion.Z motion.W, or "
                         "Blender's Vector pass) — render the G-buffer with animation");
        return false;
    }
    if (channels.depth < 0) {
        tool.fail(path + ": no depth channel (Z, or Blender's Depth.Z)");
        return false;
    }
    const int chbegin = std::min(channels.motion, channels.depth);
    const int chend = std::max(channels.motion + 4, channels.depth + 1);
    channels.motion -= chbegin;
    channels.depth -= chbegin;
    std::string error;
    if (!reader.open(path, part, chbegin, chend, tool.threads(), error, true)) {
        tool.fail(cannotRead(path, error));
        return false;
    }
    return true;
}

int run(int argc, char** argv) {
    app::CommandLine cl(
        "dhdr-motionblur", "HDR.exr -o HDR.exr [--gbuffer GBUFFER.exr] [options]",
        "Motion blur in post, in linear HDR (McGuire et al. 2012, \"A reconstruction filter for\n"
        "plausible motion blur\"): each pixel gathers taps along the longest motion of its\n"
        "neighbourhood, weighted by depth so that what is in front streaks over what is\n"
        "behind. Motion comes from --gbuffer (or the input's own channels): dhdr's motion.X …\n"
        "motion.W or Blender's Vector pass (X,Y = previous − now, Z,W = now − next, pixels,\n"
        "y up), with depth from Z or Depth.Z. Run it before tone mapping, so that highlights\n"
        "streak with their energy. Pixels with no motion nearby are copied bit for bit.");
    MotionBlurParams params;
    std::string gbufferPath, layer;
    cl.option("--gbuffer", gbufferPath, "FILE", "G-buffer with the motion and depth channels");
    app::addParamOptions(cl, params, kMotionBlurFloatTable);
    app::addParamOptions(cl, params, kMotionBlurIntTable);
    cl.option("--layer", layer, "NAME",
              "the layer or EXR part to blur (default: the unnamed R,G,B,A, else the one "
              "called Combined, rgba or beauty)");
    cl.epilog("Example:\n  dhdr-motionblur shot.0001.aa.exr --gbuffer shot.0001.gbuf.exr -o "
              "shot.0001.mb.exr --shutter 0.5");
    cl.namesFile("--gbuffer", app::FileRole::Input);
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-motionblur", cl);
    if (cl.inputs().size() != 1) {
        std::fprintf(stderr, "dhdr-motionblur: usage error: give one HDR image\n");
        return app::kExitUsage;
    }
    std::vector<std::string> paths = cl.inputs();
    if (!gbufferPath.empty()) paths.push_back(gbufferPath);
    app::FramePlan plan;
    if (const int status = app::planFrames(tool, paths, plan); status >= 0) return status;
    return app::runFrames(tool, plan, [&](int, const auto& in, const auto& out) {
        const std::string& path = in[0];
        const std::string& geometryPath = in.size() > 1 ? in[1] : path;
        ColourStripReader colour;
        if (!tool.openColour(path, layer, true, colour)) return false;
        StripReader gbuffer;
        MotionChannels channels;
        if (!openGeometry(tool, geometryPath, gbuffer, channels)) return false;
        const OIIO::ImageSpec& frame = colour.spec();
        if (gbuffer.spec().width != frame.width || gbuffer.spec().height != frame.height ||
            gbuffer.spec().x != frame.x || gbuffer.spec().y != frame.y) {
            tool.fail(geometryPath + ": is " + std::to_string(gbuffer.spec().width) + "x" +
                      std::to_string(gbuffer.spec().height) + " but " + path + " is " +
                      std::to_string(frame.width) + "x" + std::to_string(frame.height));
            return false;
        }
        const int ncolour = frame.alpha_channel == 3 ? 4 : 3;
        OIIO::ImageSpec spec = frame;
        spec.attribute("dhdr:motionBlurShutter", params.shutter);
        app::AtomicOutput file(tool, out);
        if (!file.open(spec, colour.formats())) return false;
        StripPipelineParams strips;
        strips.halo = motionBlurReach(params);
        // Strips several halos tall: the halo's rows are read and their velocities found again
        // for every strip.
        strips.rows = std::max(strips.rows, 4 * strips.halo);
        strips.nthreads = tool.threads();
        app::Progress progress(tool, "dhdr-motionblur: " + path);
        strips.progress = progress.over();
        StripPipeline pipeline(OIIO::get_roi(frame), strips);
        pipeline.addInput({[&](int y0, int y1, OIIO::ImageBuf& s, std::string& e) {
                               return colour.read(y0, y1, s, e);
                           },
                           path,
                           {{0, ncolour}}});
        // Motion is sanitized (a NaN vector would be no motion anyway); depth keeps its +∞.
        pipeline.addInput({[&](int y0, int y1, OIIO::ImageBuf& s, std::string& e) {
                               return gbuffer.read(y0, y1, s, e);
                           },
                           geometryPath,
                           {{channels.motion, channels.motion + 4}}});
        pipeline.setOutput(file.file());
        OIIO::ImageBuf motion, depth;
        const bool ran = pipeline.run([&](StripContext& strip) {
            const OIIO::ImageBuf& image = *strip.inputs[0];
            const OIIO::ImageBuf& geometry = *strip.inputs[1];
            const int m[4] = {channels.motion, channels.motion + 1, channels.motion + 2,
                              channels.motion + 3};
            OIIO::ImageBufAlgo::channels(motion, geometry, 4, m);
            OIIO::ImageBufAlgo::channels(depth, geometry, 1, &channels.depth);
            OIIO::ROI core = image.roi();
            core.ybegin = strip.rows.ybegin;
            core.yend = strip.rows.yend;
            strip.output->copy(image);
            if (!motionBlur(*strip.output, image, motion, depth, params, core, tool.threads())) {
                strip.error = path + ": " + strip.output->geterror();
                return false;
            }
            return true;
        });
        if (!ran) {
            tool.fail(pipeline.error());
            return false;
        }
        if (!file.commit()) return false;
        tool.reportNonFinite(path, pipeline.replaced()[0], false);
        tool.reportNonFinite(geometryPath, pipeline.replaced()[1], false);
        return true;
    });
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-motionblur", [&] { return run(argc, argv); });
}
