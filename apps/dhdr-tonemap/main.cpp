// dhdr-tonemap: linear HDR in, a display image out (docs/tools.md).
#include "../common/tool.h"

#include <dhdr/tonemap/display.h>
#include <dhdr/tonemap/reinhard.h>
#include <dhdr/tonemap/tone_map.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

using namespace dhdr;

namespace {

int usage(const char* message) {
    std::fprintf(stderr, "dhdr-tonemap: usage error: %s\nTry 'dhdr-tonemap --help'.\n", message);
    return app::kExitUsage;
}

} // namespace

int main(int argc, char** argv) {
    app::CommandLine cl("dhdr-tonemap", "HDR.exr -o IMAGE.png [options]",
                        "Tone mapping: meters the image's luminance, maps it with an operator "
                        "(default the\nphotographic operator of Reinhard et al. 2002) and encodes "
                        "it for an sRGB display.\nPNG (8- or 16-bit), JPEG and TIFF are "
                        "sRGB-encoded, 8-bit output dithered; EXR output\nkeeps display-linear "
                        "half floats.");
    double key = 0.18, exposure = 0.0, delta = 1e-4;
    std::string white = "auto", weights = "seed", opName = "reinhard", metering = "log-average",
                percentiles = "5,95";
    int bits = 8;
    bool noDither = false;
    cl.option("--op", opName, "NAME",
              "reinhard (default), reinhard-local, drago, hable, pbr-neutral or exposure");
    cl.option("--key", key, "A", "key α: the metered luminance maps to this (default 0.18)");
    cl.option("--exposure", exposure, "STOPS", "extra exposure in stops (default 0)");
    cl.option("--white", white, "L|auto|inf",
              "reinhard's white point in scaled luminance (default auto: the largest in the "
              "image; inf: L/(1+L))");
    cl.option("--metering", metering, "log-average|histogram",
              "the log-average of all pixels (default), or of those between two percentiles");
    cl.option("--percentiles", percentiles, "LO,HI",
              "the percentile window of --metering histogram (default 5,95)");
    cl.option("--weights", weights, "seed|rec709",
              "luminance weights: 0.27/0.67/0.06 (default) or 0.2126/0.7152/0.0722");
    cl.option("--delta", delta, "D", "δ of the log-average (default 1e-4)");
    cl.option("--bits", bits, "8|16", "bits per channel of PNG/TIFF output (default 8)");
    cl.flag("--no-dither", noDither, "quantize 8-bit output without dithering");
    cl.epilog("Example:\n  dhdr-tonemap frame.hdr.exr -o frame.png -v\n"
              "  dhdr-tonemap frame.hdr.exr --op hable --exposure 0.5 -o frame.jpg");
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-tonemap", cl);
    if (cl.inputs().size() != 1) return usage("give one HDR image");

    ToneMapParams params;
    if (!parseToneOperator(opName, params.op))
        return usage("--op must be reinhard, reinhard-local, drago, hable, pbr-neutral or exposure");
    params.key = key;
    params.exposure = exposure;
    LuminanceStatsParams& lum = params.metering.luminance;
    lum.delta = delta;
    if (weights == "seed")
        lum.weights = kSeedLuminanceWeights;
    else if (weights == "rec709")
        lum.weights = kRec709LuminanceWeights;
    else
        return usage("--weights must be seed or rec709");
    if (metering == "histogram")
        params.metering.mode = MeteringMode::Histogram;
    else if (metering != "log-average")
        return usage("--metering must be log-average or histogram");
    std::vector<double> window;
    if (!app::parseNumbers(percentiles, window, 2) || !(window[0] >= 0.0) ||
        !(window[0] < window[1]) || !(window[1] <= 100.0))
        return usage("--percentiles must be LO,HI with 0 <= LO < HI <= 100");
    params.metering.lowPercentile = window[0];
    params.metering.highPercentile = window[1];
    if (white == "inf")
        params.white = INFINITY;
    else if (white != "auto") {
        char* end = nullptr;
        params.white = std::strtod(white.c_str(), &end);
        if (*end != '\0' || !(params.white > 0.0))
            return usage("--white must be a positive number, auto or inf");
    }
    if (!(key > 0.0) || !(delta > 0.0) || (bits != 8 && bits != 16))
        return usage("--key and --delta must be positive, --bits 8 or 16");
    const std::string& path = cl.inputs()[0];
    if (const int status = tool.start(cl.inputs()); status >= 0) return status;

    OIIO::ImageBuf hdr;
    if (!tool.readImage(path, hdr)) return app::kExitFailure;
    if (hdr.nchannels() < 3)
        return tool.fail(path + ": has " + std::to_string(hdr.nchannels()) +
                         " channels; tone mapping needs R, G, B");
    // A display shows no negative light: negatives go with NaN and Inf, in one warning.
    tool.replaceNonFinite(path, hdr, 0, 3, true);
    if (hdr.nchannels() >= 4) tool.replaceNonFinite(path, hdr, 3, 4);

    LuminanceStats stats;
    meter(stats, hdr, params.metering, {}, tool.threads());
    params.stats = &stats;
    char line[256];
    std::snprintf(line, sizeof line, "%s metering: %.6g (largest luminance %.6g, %lld pixels)",
                  metering.c_str(), stats.logAverage, stats.maxLuminance, stats.pixels);
    tool.info(line);
    if (params.op == ToneOperator::Reinhard) {
        ReinhardParams rp;
        rp.key = key;
        rp.exposure = exposure;
        rp.white = params.white;
        const ReinhardMapping mapping = resolveReinhard(stats, rp);
        std::snprintf(line, sizeof line, "reinhard: scale %.6g, white %.6g (scaled)",
                      mapping.scale, mapping.white);
        tool.info(line);
    }

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
    if (!toneMap(mapped, hdr, params, {}, tool.threads()))
        return tool.fail(path + ": " + mapped.geterror());

    std::string ext = std::filesystem::path(cl.output()).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    OIIO::ImageSpec& out = mapped.specmod();
    // Strings, which every format keeps (PNG drops numeric attributes).
    out.attribute("dhdr:toneMap", toneOperatorName(params.op));
    std::snprintf(line, sizeof line,
                  "key %g, exposure %g, white %s, weights %s, delta %g, metering %s %s -> %.6g",
                  key, exposure, white.c_str(), weights.c_str(), delta, metering.c_str(),
                  metering == "histogram" ? percentiles.c_str() : "", stats.logAverage);
    out.attribute("dhdr:toneMapParameters", line);
    out.attribute("dhdr:source", path);
    if (ext == ".exr") {
        out.attribute("oiio:ColorSpace", "Linear");
        return tool.writeImage(mapped, cl.output(), {OIIO::TypeDesc::HALF}) ? 0 : 1;
    }
    encodeSRGB(mapped, mapped, {}, tool.threads());
    out.attribute("oiio:ColorSpace", "sRGB");
    const bool sixteen = bits == 16 && ext != ".jpg" && ext != ".jpeg";
    if (!sixteen && !noDither) {
        addDither(mapped, 8, 0, {}, tool.threads());
        out.attribute("dhdr:dither", "triangular, 1 LSB");
    }
    const OIIO::TypeDesc type = sixteen ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8;
    return tool.writeImage(mapped, cl.output(), {type}) ? app::kExitSuccess : app::kExitFailure;
}
