// dhdr-aa: edge-detect anti-aliasing of an image from its geometry (docs/tools.md).
#include "../common/frames.h"
#include "../common/tool.h"

#include <OpenImageIO/imagebufalgo.h>
#include <dhdr/deferred/gbuffer.h>
#include <dhdr/tonemap/edge_aa.h>

using namespace dhdr;

namespace {

// The normal (N.X N.Y N.Z) and depth (Z) channels of `img`, when it has them.
bool extractGeometry(const OIIO::ImageBuf& img, OIIO::ImageBuf& normal, OIIO::ImageBuf& depth,
                     bool& hasNormal, bool& hasDepth) {
    const OIIO::ImageSpec& spec = img.spec();
    const int n = spec.channelindex(gbuffer::kNormal[0]);
    hasNormal = n >= 0 && spec.channelindex(gbuffer::kNormal[1]) == n + 1 &&
                spec.channelindex(gbuffer::kNormal[2]) == n + 2;
    const int z = spec.channelindex(gbuffer::kDepth);
    hasDepth = z >= 0;
    if (hasNormal) {
        const int order[3] = {n, n + 1, n + 2};
        normal = OIIO::ImageBufAlgo::channels(img, 3, order);
    }
    if (hasDepth) {
        const int order[1] = {z};
        depth = OIIO::ImageBufAlgo::channels(img, 1, order);
    }
    return hasNormal || hasDepth;
}

} // namespace

namespace {

int run(int argc, char** argv) {
    app::CommandLine cl("dhdr-aa", "HDR.exr -o HDR.exr [--gbuffer GBUFFER.exr] [options]",
                        "Edge-detect anti-aliasing: a blur factor from the squared differences of "
                        "normal and\ndepth to the 8 neighbours; where it is above zero the pixel "
                        "is resampled at\nneighbour offsets scaled by it, elsewhere copied bit for "
                        "bit. Normal and depth come\nfrom --gbuffer, or from the input's own N.* "
                        "and Z channels.");
    std::string gbufferPath, use = "both", layer;
    double normalWeight = 1.0, depthWeight = 1.0, maxOffset = 0.5;
    cl.option("--gbuffer", gbufferPath, "FILE", "G-buffer with N.X N.Y N.Z and Z");
    cl.option("--use", use, "normal|depth|both", "which discontinuities count (default both)");
    cl.option("--normal-weight", normalWeight, "W", "weight of Σ|ΔN|² (default 1)", {0.0, 1e6});
    cl.option("--depth-weight", depthWeight, "W", "weight of Σ(ΔZ/Z)² (default 1)", {0.0, 1e6});
    cl.option("--max-offset", maxOffset, "PX", "tap offset at full blur, pixels (default 0.5)",
              {0.0, 4.0});
    cl.option("--layer", layer, "NAME",
              "the layer or EXR part to filter (default: the unnamed R,G,B,A, else the one "
              "called Combined, rgba or beauty)");
    cl.epilog("Example:\n  dhdr-aa frame.hdr.exr --gbuffer frame.gbuf.exr -o frame.aa.exr");
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
    EdgeAAParams params;
    params.normalWeight = float(normalWeight);
    params.depthWeight = float(depthWeight);
    params.maxOffset = float(maxOffset);
    const std::vector<std::string> geometryChannels = {gbuffer::kDepth, gbuffer::kNormal[0],
                                                       gbuffer::kNormal[1], gbuffer::kNormal[2]};
    return app::runFrames(tool, plan, [&](int, const auto& in, const auto& out) {
        const std::string& path = in[0];
        const bool separate = in.size() > 1;
        OIIO::ImageBuf image, gbuf;
        std::vector<OIIO::TypeDesc> formats;
        if (!tool.readColour(path, layer, true, image, formats, tool.threads())) return false;
        tool.warnIfEmpty(path, image);
        const std::string& geometryPath = separate ? in[1] : path;
        if (separate && !tool.readImageChannels(geometryPath, geometryChannels, gbuf)) return false;
        const OIIO::ImageBuf& geometry = separate ? gbuf : image;
        if (geometry.spec().width != image.spec().width ||
            geometry.spec().height != image.spec().height) {
            tool.fail(geometryPath + ": is " + std::to_string(geometry.spec().width) + "x" +
                      std::to_string(geometry.spec().height) + " but " + path + " is " +
                      std::to_string(image.spec().width) + "x" +
                      std::to_string(image.spec().height));
            return false;
        }
        OIIO::ImageBuf normal, depth;
        bool hasNormal = false, hasDepth = false;
        extractGeometry(geometry, normal, depth, hasNormal, hasDepth);
        if (use != "depth" && !hasNormal) {
            tool.fail(geometryPath + ": no channel 'N.X' — give a G-buffer with --gbuffer");
            return false;
        }
        if (use != "normal" && !hasDepth) {
            tool.fail(geometryPath + ": no channel 'Z' — give a G-buffer with --gbuffer");
            return false;
        }
        // The layer's R, G, B (A) come first (readColour); nothing else is filtered.
        const int colour = image.spec().alpha_channel == 3 ? 4 : 3;
        tool.replaceNonFinite(path, image, 0, colour);
        if (hasNormal) tool.replaceNonFinite(geometryPath, normal, 0, 3);
        // Only colour is filtered; geometry channels carried by the image stay as they are.
        OIIO::ROI roi = image.roi();
        roi.chend = colour;
        OIIO::ImageBuf result = image.copy(OIIO::TypeDesc::FLOAT);
        if (!edgeAA(result, image, use != "depth" ? &normal : nullptr,
                    use != "normal" ? &depth : nullptr, params, roi, tool.threads())) {
            tool.fail(path + ": " + result.geterror());
            return false;
        }
        return tool.writeImage(result, out, formats);
    });
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-aa", [&] { return run(argc, argv); });
}
