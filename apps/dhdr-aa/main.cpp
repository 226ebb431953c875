// dhdr-aa: edge-detect anti-aliasing of an image from its geometry (docs/tools.md).
#include "../common/frames.h"
#include "../common/param_options.h"
#include "../common/tool.h"

#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <cmath>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/io/layers.h>
#include <dhdr/io/sanitize.h>
#include <dhdr/io/strip_pipeline.h>
#include <dhdr/io/strip_reader.h>
#include <dhdr/tonemap/edge_aa.h>
#include <memory>

using namespace dhdr;

namespace {

// Where the normal (N.X N.Y N.Z, in order) and depth (Z) channels are; −1 when absent.
struct GeometryChannels {
    int normal = -1, depth = -1;
};

GeometryChannels findGeometry(const OIIO::ImageSpec& spec) {
    GeometryChannels g;
    const int n = spec.channelindex(gbuffer::kNormal[0]);
    if (n >= 0 && spec.channelindex(gbuffer::kNormal[1]) == n + 1 &&
        spec.channelindex(gbuffer::kNormal[2]) == n + 2)
        g.normal = n;
    g.depth = spec.channelindex(gbuffer::kDepth);
    return g;
}

// The normal and depth channels of a strip, as images of their own.
void extractGeometry(const OIIO::ImageBuf& img, const GeometryChannels& g, OIIO::ImageBuf& normal,
                     OIIO::ImageBuf& depth) {
    if (g.normal >= 0) {
        const int order[3] = {g.normal, g.normal + 1, g.normal + 2};
        OIIO::ImageBufAlgo::channels(normal, img, 3, order);
    }
    if (g.depth >= 0) {
        const int order[1] = {g.depth};
        OIIO::ImageBufAlgo::channels(depth, img, 1, order);
    }
}

const std::vector<std::string> kGeometryChannels = {gbuffer::kDepth, gbuffer::kNormal[0],
                                                    gbuffer::kNormal[1], gbuffer::kNormal[2]};

// Opens the geometry of a separate G-buffer: the smallest run of channels of its first part
// holding Z or N.* (a multi-part G-buffer), a deep one's front surfaces. False after the
// tool's error.
bool openGeometry(const app::Tool& tool, const std::string& geometryPath, StripReader& gbuffer) {
    OIIO::ImageSpec spec;
    const int part = tool.findPart(
        geometryPath,
        [](const OIIO::ImageSpec& spec) {
            return std::any_of(kGeometryChannels.begin(), kGeometryChannels.end(),
                               [&](const std::string& n) { return spec.channelindex(n) >= 0; });
        },
        spec);
    if (part < 0) return false;
    int chbegin = spec.nchannels, chend = 0;
    for (const std::string& name : kGeometryChannels)
        if (const int c = spec.channelindex(name); c >= 0) {
            chbegin = std::min(chbegin, c);
            chend = std::max(chend, c + 1);
        }
    if (chend <= chbegin) chbegin = 0, chend = spec.nchannels;
    std::string error;
    if (!gbuffer.open(geometryPath, part, chbegin, chend, tool.threads(), error, true)) {
        tool.fail(cannotRead(geometryPath, error));
        return false;
    }
    return true;
}

// The geometry's channels, checked against the frame and against --use. False after the
// tool's error.
bool checkGeometry(const app::Tool& tool, const std::string& path, const std::string& geometryPath,
                   const OIIO::ImageSpec& frame, const OIIO::ImageSpec& geometrySpec,
                   const std::string& use, GeometryChannels& channels) {
    if (geometrySpec.width != frame.width || geometrySpec.height != frame.height) {
        tool.fail(geometryPath + ": is " + std::to_string(geometrySpec.width) + "x" +
                  std::to_string(geometrySpec.height) + " but " + path + " is " +
                  std::to_string(frame.width) + "x" + std::to_string(frame.height));
        return false;
    }
    channels = findGeometry(geometrySpec);
    if (use != "depth" && channels.normal < 0) {
        tool.fail(geometryPath + ": no channel 'N.X' — give a G-buffer with --gbuffer");
        return false;
    }
    if (use != "normal" && channels.depth < 0) {
        tool.fail(geometryPath + ": no channel 'Z' — give a G-buffer with --gbuffer");
        return false;
    }
    return true;
}

// What filtering one frame needs.
struct AAFrame {
    std::string path, geometryPath, out, use;
    bool separate = false;
    ColourStripReader colour;
    StripReader gbuffer;
    GeometryChannels channels;
};

// Filters the frame strip by strip with a halo: each output row sees the rows it would see
// in the whole frame, so the result does not depend on the strips, and memory stays at a
// strip.
bool filterFrame(const app::Tool& tool, AAFrame& f, const EdgeAAParams& params) {
    const OIIO::ImageSpec& frame = f.colour.spec();
    // The layer's R, G, B (A) come first (ColourStripReader); nothing else is filtered.
    const int ncolour = frame.alpha_channel == 3 ? 4 : 3;
    app::AtomicOutput file(tool, f.out);
    if (!file.open(frame, f.colour.formats())) return false;
    StripPipelineParams strips;
    // Rows above and below each strip that its pixels read: one for the blur factor's
    // neighbours, and the taps' reach.
    strips.halo = int(std::ceil(params.maxOffset)) + 2;
    strips.nthreads = tool.threads();
    app::Progress progress(tool, "dhdr-aa: " + f.path);
    strips.progress = progress.over();
    StripPipeline pipeline(OIIO::get_roi(frame), strips);
    std::vector<std::pair<int, int>> colourChannels = {{0, ncolour}}, normalChannels;
    if (f.channels.normal >= 0)
        (f.separate ? normalChannels : colourChannels)
            .emplace_back(f.channels.normal, f.channels.normal + 3);
    pipeline.addInput({[&](int y0, int y1, OIIO::ImageBuf& s, std::string& e) {
                           return f.colour.read(y0, y1, s, e);
                       },
                       f.path, colourChannels});
    if (f.separate)
        pipeline.addInput({[&](int y0, int y1, OIIO::ImageBuf& s, std::string& e) {
                               return f.gbuffer.read(y0, y1, s, e);
                           },
                           f.geometryPath, normalChannels});
    pipeline.setOutput(file.file());
    OIIO::ImageBuf normal, depth;
    bool anySurface = false;
    const bool run = pipeline.run([&](StripContext& strip) {
        const OIIO::ImageBuf& image = *strip.inputs[0];
        extractGeometry(f.separate ? *strip.inputs[1] : image, f.channels, normal, depth);
        OIIO::ROI core = image.roi();
        core.ybegin = strip.rows.ybegin;
        core.yend = strip.rows.yend;
        core.chend = ncolour;
        anySurface = anySurface || app::hasSurface(image, core);
        strip.output->copy(image);
        if (!edgeAA(*strip.output, image, f.use != "depth" ? &normal : nullptr,
                    f.use != "normal" ? &depth : nullptr, params, core, tool.threads())) {
            strip.error = f.path + ": " + strip.output->geterror();
            return false;
        }
        return true;
    });
    if (!run) {
        tool.fail(pipeline.error());
        return false;
    }
    const NonFiniteCount replacedColour = pipeline.replaced()[0];
    const NonFiniteCount replacedNormal = f.separate ? pipeline.replaced()[1] : NonFiniteCount();
    if (!file.commit()) return false;
    tool.reportNonFinite(f.path, replacedColour, false);
    tool.reportNonFinite(f.geometryPath, replacedNormal, false);
    if (!anySurface) tool.warnNoSurface(f.path);
    return true;
}

int run(int argc, char** argv) {
    app::CommandLine cl("dhdr-aa", "HDR.exr -o HDR.exr [--gbuffer GBUFFER.exr] [options]",
                        "Edge-detect anti-aliasing: a blur factor from the squared differences of "
                        "normal and\ndepth to the 8 neighbours; where it is above zero the pixel "
                        "is resampled at\nneighbour offsets scaled by it, elsewhere copied bit for "
                        "bit. Normal and depth come\nfrom --gbuffer, or from the input's own N.* "
                        "and Z channels.");
    std::string gbufferPath, use = "both", layer;
    EdgeAAParams params; // the options write into it
    cl.option("--gbuffer", gbufferPath, "FILE", "G-buffer with N.X N.Y N.Z and Z");
    cl.option("--use", use, "normal|depth|both", "which discontinuities count");
    app::addParamOptions(cl, params, kEdgeAAFloatTable);
    cl.option("--layer", layer, "NAME",
              "the layer or EXR part to filter (default: the unnamed R,G,B,A, else the one "
              "called Combined, rgba or beauty)");
    cl.epilog("Example:\n  dhdr-aa frame.hdr.exr --gbuffer frame.gbuf.exr -o frame.aa.exr");
    cl.namesFile("--gbuffer", app::FileRole::Input);
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-aa", cl);
    if (cl.inputs().size() != 1) {
        std::fprintf(stderr, "dhdr-aa: usage error: give one image\n");
        return app::kExitUsage;
    }
    if (use != "normal" && use != "depth" && use != "both") {
        std::fprintf(stderr, "dhdr-aa: usage error: --use must be normal, depth or both\n");
        return app::kExitUsage;
    }
    std::vector<std::string> paths = cl.inputs();
    if (!gbufferPath.empty()) paths.push_back(gbufferPath);
    app::FramePlan plan;
    if (const int status = app::planFrames(tool, paths, plan); status >= 0) return status;
    return app::runFrames(tool, plan, [&](int, const auto& in, const auto& out) {
        AAFrame f;
        f.path = in[0];
        f.out = out;
        f.use = use;
        f.separate = in.size() > 1;
        f.geometryPath = f.separate ? in[1] : f.path;
        if (!tool.openColour(f.path, layer, true, f.colour)) return false;
        if (f.separate && !openGeometry(tool, f.geometryPath, f.gbuffer)) return false;
        const OIIO::ImageSpec& frame = f.colour.spec();
        return checkGeometry(tool, f.path, f.geometryPath, frame,
                             f.separate ? f.gbuffer.spec() : frame, use, f.channels) &&
               filterFrame(tool, f, params);
    });
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-aa", [&] { return run(argc, argv); });
}
