// dhdr-tonemap: linear HDR in, a display image out (docs/tools.md).
#include "../common/tool.h"

#include <dhdr/tonemap/display.h>
#include <dhdr/tonemap/reinhard.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

using namespace dhdr;

int main(int argc, char** argv) {
    app::CommandLine cl("dhdr-tonemap", "HDR.exr -o IMAGE.png [options]",
                        "Photographic tone mapping (Reinhard et al. 2002): meters the log-average "
                        "luminance,\nscales it to the key, compresses with a white point, and "
                        "encodes for an sRGB display.\nPNG (8- or 16-bit) and the other formats "
                        "OpenImageIO writes are sRGB-encoded; EXR\noutput keeps display-linear "
                        "half floats.");
    double key = 0.18, exposure = 0.0, delta = 1e-4;
    std::string white = "auto", weights = "seed";
    int bits = 8;
    cl.option("--key", key, "A", "key α: the log-average maps to this (default 0.18)");
    cl.option("--exposure", exposure, "STOPS", "extra exposure in stops (default 0)");
    cl.option("--white", white, "L|auto|inf",
              "white point in scaled luminance (default auto: the largest in the image; "
              "inf: L/(1+L))");
    cl.option("--weights", weights, "seed|rec709",
              "luminance weights: 0.27/0.67/0.06 (default) or 0.2126/0.7152/0.0722");
    cl.option("--delta", delta, "D", "δ of the log-average (default 1e-4)");
    cl.option("--bits", bits, "8|16", "bits per channel of PNG/TIFF output (default 8)");
    cl.epilog("Example:\n  dhdr-tonemap frame.hdr.exr -o frame.png -v");
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-tonemap", cl);
    if (cl.inputs().size() != 1) {
        std::fprintf(stderr, "dhdr-tonemap: usage error: give one HDR image\n");
        return app::kExitUsage;
    }
    ReinhardParams params;
    params.key = key;
    params.exposure = exposure;
    params.metering.delta = delta;
    if (weights == "seed")
        params.metering.weights = kSeedLuminanceWeights;
    else if (weights == "rec709")
        params.metering.weights = kRec709LuminanceWeights;
    else {
        std::fprintf(stderr, "dhdr-tonemap: usage error: --weights must be seed or rec709\n");
        return app::kExitUsage;
    }
    if (white == "inf")
        params.white = INFINITY;
    else if (white != "auto") {
        char* end = nullptr;
        params.white = std::strtod(white.c_str(), &end);
        if (*end != '\0' || !(params.white > 0.0)) {
            std::fprintf(stderr, "dhdr-tonemap: usage error: --white must be a positive number, "
                                 "auto or inf\n");
            return app::kExitUsage;
        }
    }
    if (!(key > 0.0) || !(delta > 0.0) || (bits != 8 && bits != 16)) {
        std::fprintf(stderr, "dhdr-tonemap: usage error: --key and --delta must be positive, "
                             "--bits 8 or 16\n");
        return app::kExitUsage;
    }
    const std::string& path = cl.inputs()[0];
    if (const int status = tool.start(cl.inputs()); status >= 0) return status;

    OIIO::ImageBuf hdr;
    if (!tool.readImage(path, hdr)) return app::kExitFailure;
    if (hdr.nchannels() < 3)
        return tool.fail(path + ": has " + std::to_string(hdr.nchannels()) +
                         " channels; tone mapping needs R, G, B");
    tool.replaceNonFinite(path, hdr, 0, std::min(hdr.nchannels(), 4));

    LuminanceStats stats;
    computeLuminanceStats(stats, hdr, params.metering, {}, tool.threads());
    if (stats.negativePixels > 0)
        tool.warn(path + ": " + std::to_string(stats.negativePixels) +
                  " pixels have negative luminance; metered as 0");
    params.stats = &stats;
    const ReinhardMapping mapping = resolveReinhard(stats, params);
    char line[256];
    std::snprintf(line, sizeof line,
                  "log-average luminance %.6g, max %.6g; scale %.6g, white %.6g (scaled)",
                  stats.logAverage, stats.maxLuminance, mapping.scale, mapping.white);
    tool.info(line);

    // Only R, G, B (and alpha) go to a display image.
    const int nch = std::min(hdr.nchannels(), 4);
    OIIO::ImageSpec spec = hdr.spec();
    spec.nchannels = nch;
    spec.channelnames.resize(size_t(nch));
    spec.alpha_channel = nch == 4 ? 3 : -1;
    spec.z_channel = -1;
    spec.channelformats.clear();
    spec.set_format(OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf mapped(spec);
    if (!reinhard(mapped, hdr, params, {}, tool.threads()))
        return tool.fail(path + ": " + mapped.geterror());
    std::string ext = std::filesystem::path(cl.output()).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    OIIO::ImageSpec& out = mapped.specmod();
    out.attribute("dhdr:toneMap", "reinhard");
    out.attribute("dhdr:key", float(key));
    out.attribute("dhdr:exposure", float(exposure));
    out.attribute("dhdr:white", float(mapping.white));
    out.attribute("dhdr:logAverage", float(stats.logAverage));
    out.attribute("dhdr:source", path);
    if (ext == ".exr") {
        out.attribute("oiio:ColorSpace", "Linear");
        return tool.writeImage(mapped, cl.output(), {OIIO::TypeDesc::HALF}) ? 0 : 1;
    }
    if (!encodeSRGB(mapped, mapped, {}, tool.threads()))
        return tool.fail(path + ": " + mapped.geterror());
    out.attribute("oiio:ColorSpace", "sRGB");
    const OIIO::TypeDesc type = bits == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8;
    return tool.writeImage(mapped, cl.output(), {type}) ? app::kExitSuccess : app::kExitFailure;
}
