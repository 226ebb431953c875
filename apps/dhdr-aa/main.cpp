// dhdr-aa: edge-detect anti-aliasing of an image from its geometry (docs/tools.md).
#include "../common/tool.h"

#include <dhdr/deferred/gbuffer.h>
#include <dhdr/tonemap/edge_aa.h>

#include <OpenImageIO/imagebufalgo.h>

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

int main(int argc, char** argv) {
    app::CommandLine cl("dhdr-aa", "HDR.exr -o HDR.exr [--gbuffer GBUFFER.exr] [options]",
                        "Edge-detect anti-aliasing: a blur factor from the squared differences of "
                        "normal and\ndepth to the 8 neighbours; where it is above zero the pixel "
                        "is resampled at\nneighbour offsets scaled by it, elsewhere copied bit for "
                        "bit. Normal and depth come\nfrom --gbuffer, or from the input's own N.* "
                        "and Z channels.");
    std::string gbufferPath, use = "both";
    double normalWeight = 1.0, depthWeight = 1.0, maxOffset = 0.5;
    cl.option("--gbuffer", gbufferPath, "FILE", "G-buffer with N.X N.Y N.Z and Z");
    cl.option("--use", use, "normal|depth|both", "which discontinuities count (default both)");
    cl.option("--normal-weight", normalWeight, "W", "weight of Σ|ΔN|² (default 1)");
    cl.option("--depth-weight", depthWeight, "W", "weight of Σ(ΔZ/Z)² (default 1)");
    cl.option("--max-offset", maxOffset, "PX", "tap offset at full blur, pixels (default 0.5)");
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
    const std::string& path = cl.inputs()[0];
    std::vector<std::string> inputs = cl.inputs();
    if (!gbufferPath.empty()) inputs.push_back(gbufferPath);
    if (const int status = tool.start(inputs); status >= 0) return status;

    OIIO::ImageBuf image, gbuf;
    if (!tool.readImage(path, image)) return app::kExitFailure;
    const std::string& geometryPath = gbufferPath.empty() ? path : gbufferPath;
    const std::vector<std::string> geometryChannels = {gbuffer::kDepth, gbuffer::kNormal[0],
                                                       gbuffer::kNormal[1], gbuffer::kNormal[2]};
    if (!gbufferPath.empty() && !tool.readImageChannels(gbufferPath, geometryChannels, gbuf))
        return app::kExitFailure;
    const OIIO::ImageBuf& geometry = gbufferPath.empty() ? image : gbuf;
    if (geometry.spec().width != image.spec().width ||
        geometry.spec().height != image.spec().height)
        return tool.fail(geometryPath + ": is " + std::to_string(geometry.spec().width) + "x" +
                         std::to_string(geometry.spec().height) + " but " + path + " is " +
                         std::to_string(image.spec().width) + "x" +
                         std::to_string(image.spec().height));

    OIIO::ImageBuf normal, depth;
    bool hasNormal = false, hasDepth = false;
    extractGeometry(geometry, normal, depth, hasNormal, hasDepth);
    if (use != "depth" && !hasNormal)
        return tool.fail(geometryPath + ": no channel 'N.X' — give a G-buffer with --gbuffer");
    if (use != "normal" && !hasDepth)
        return tool.fail(geometryPath + ": no channel 'Z' — give a G-buffer with --gbuffer");
    const int colour = std::min(image.nchannels(), 4);
    tool.replaceNonFinite(path, image, 0, colour);
    if (hasNormal) tool.replaceNonFinite(geometryPath, normal, 0, 3);

    EdgeAAParams params;
    params.normalWeight = float(normalWeight);
    params.depthWeight = float(depthWeight);
    params.maxOffset = float(maxOffset);
    // Only colour is filtered; geometry channels carried by the image stay as they are.
    OIIO::ROI roi = image.roi();
    roi.chend = colour;
    OIIO::ImageBuf out = image.copy(OIIO::TypeDesc::FLOAT);
    if (!edgeAA(out, image, use != "depth" ? &normal : nullptr, use != "normal" ? &depth : nullptr,
                params, roi, tool.threads()))
        return tool.fail(path + ": " + out.geterror());
    std::vector<OIIO::TypeDesc> formats = image.nativespec().channelformats;
    if (formats.empty()) formats = {image.nativespec().format};
    return tool.writeImage(out, cl.output(), formats) ? app::kExitSuccess : app::kExitFailure;
}
