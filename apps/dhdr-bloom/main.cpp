// dhdr-bloom: linear HDR in, the same with bloom added out (docs/tools.md).
#include "../common/frames.h"
#include "../common/tool.h"

#include <dhdr/tonemap/bloom.h>

using namespace dhdr;

int main(int argc, char** argv) {
    app::CommandLine cl("dhdr-bloom", "HDR.exr -o HDR.exr [options]",
                        "Bloom in HDR: a quarter-size copy, a bright pass (8-tap box, kept where "
                        "the tone-mapped\nluminance exceeds the threshold), downsampled to 1/8, a "
                        "separable Gaussian, upsampled\nbilinearly and added to R, G, B. Other "
                        "channels pass through unchanged.");
    BloomParams params;
    double threshold = params.threshold, sigma = params.sigma, strength = params.strength,
           key = params.key;
    cl.option("--threshold", threshold, "T",
              "tone-mapped luminance L/(1+L) above which pixels bloom (default 0.8)");
    cl.option("--key", key, "A", "key α of that tone mapping (default 0.18)");
    cl.option("--sigma", sigma, "S", "Gaussian σ in 1/8-size pixels (default 2)");
    cl.option("--strength", strength, "K", "factor of the bloom layer (default 1.3)");
    cl.epilog("Example:\n  dhdr-bloom frame.hdr.exr -o frame.bloom.exr --strength 0.8");
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-bloom", cl);
    if (cl.inputs().size() != 1) {
        std::fprintf(stderr, "dhdr-bloom: usage error: give one HDR image\n");
        return app::kExitUsage;
    }
    if (!(sigma >= 0.0) || !(key > 0.0) || !(threshold >= 0.0 && threshold < 1.0)) {
        std::fprintf(stderr, "dhdr-bloom: usage error: --sigma >= 0, --key > 0 and "
                             "--threshold in [0, 1) please\n");
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
        if (!tool.readImage(path, hdr)) return false;
        if (hdr.nchannels() < 3) {
            tool.fail(path + ": has " + std::to_string(hdr.nchannels()) +
                      " channels; bloom needs R, G, B");
            return false;
        }
        tool.replaceNonFinite(path, hdr, 0, 3);
        if (!bloom(hdr, hdr, params, {}, tool.threads())) {
            tool.fail(path + ": " + hdr.geterror());
            return false;
        }
        hdr.specmod().attribute("dhdr:bloomStrength", float(strength));
        std::vector<OIIO::TypeDesc> formats = hdr.nativespec().channelformats;
        if (formats.empty()) formats = {hdr.nativespec().format};
        return tool.writeImage(hdr, out, formats);
    });
}
