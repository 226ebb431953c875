// dhdr-bloom: linear HDR in, the same with bloom added out (docs/tools.md).
#include "../common/frames.h"
#include "../common/tool.h"

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
    double threshold = params.threshold, sigma = params.sigma, strength = params.strength,
           key = params.key;
    cl.option("--threshold", threshold, "T",
              "tone-mapped luminance L/(1+L) above which pixels bloom (default 0.8)",
              {0.0, 1.0, false, true});
    cl.option("--key", key, "A", "key α of that tone mapping (default 0.18)", {0.0, 100.0, true});
    cl.option("--sigma", sigma, "S", "Gaussian σ in 1/8-size pixels (default 2)", {0.0, 64.0});
    cl.option("--strength", strength, "K", "factor of the bloom layer (default 1.3)",
              {0.0, 1000.0});
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
    params.threshold = float(threshold);
    params.sigma = float(sigma);
    params.strength = float(strength);
    params.key = float(key);
    app::FramePlan plan;
    if (const int status = app::planFrames(tool, cl.inputs(), plan); status >= 0) return status;
    return app::runFrames(tool, plan, [&](int, const auto& in, const auto& out) {
        const std::string& path = in[0];
        OIIO::ImageBuf hdr;
        std::vector<OIIO::TypeDesc> formats;
        if (!tool.readColour(path, layer, true, hdr, formats, tool.threads())) return false;
        tool.warnIfEmpty(path, hdr);
        tool.replaceNonFinite(path, hdr, 0, 3);
        if (!bloom(hdr, hdr, params, {}, tool.threads())) {
            tool.fail(path + ": " + hdr.geterror());
            return false;
        }
        hdr.specmod().attribute("dhdr:bloomStrength", float(strength));
        return tool.writeImage(hdr, out, formats);
    });
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-bloom", [&] { return run(argc, argv); });
}
