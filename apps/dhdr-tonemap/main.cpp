// dhdr-tonemap: linear HDR in, a display image out; one frame or a sequence (docs/tools.md).
#include "../common/frames.h"
#include "../common/tool.h"
#include "frame.h"
#include "sequence_stats.h"

#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/io/sanitize.h>
#include <dhdr/tonemap/adaptation.h>
#include <dhdr/tonemap/display_transform.h>
#include <dhdr/tonemap/quantize.h>
#include <dhdr/tonemap/reinhard.h>
#include <dhdr/tonemap/tone_map.h>
#include <filesystem>
#include <mutex>

using namespace dhdr;
using app::FrameJob;

namespace {

int usage(const std::string& message) {
    std::fprintf(stderr, "dhdr-tonemap: usage error: %s\nTry 'dhdr-tonemap --help'.\n",
                 message.c_str());
    return app::kExitUsage;
}

// "frames done, rate, time left" on a terminal.
class SequenceProgress {
public:
    SequenceProgress(const app::Tool& tool, size_t total)
        : m_progress(tool, "dhdr-tonemap"), m_total(total) {}
    void frameDone() {
        const size_t done = ++m_done;
        m_progress.update(float(done) / float(m_total));
    }

private:
    app::Progress m_progress;
    size_t m_total;
    std::atomic<size_t> m_done{0};
};

int run(int argc, char** argv) {
    app::CommandLine cl("dhdr-tonemap", "HDR.exr -o IMAGE.png [options]",
                        "Tone mapping: meters the image's luminance, maps it with an operator "
                        "(default the\nphotographic operator of Reinhard et al. 2002) in "
                        "scene-linear, and encodes it for a display\nthrough OpenColorIO (sRGB "
                        "by default). Every format gets the same display-referred\nvalues: PNG "
                        "(8- or 16-bit), JPEG and TIFF quantized, 8-bit output dithered, EXR as\n"
                        "half floats. A frame pattern (shot.####.exr or shot.%04d.exr) in\nboth "
                        "input and output maps a sequence in one process; --adapt lets the "
                        "exposure follow\nthe eye's adaptation across it.");
    double key = 0.18, exposure = 0.0, delta = 1e-4, fps = 24.0, memoryMiB = 512.0;
    FrameJob job;
    job.white = "auto";
    job.weights = "seed";
    job.metering = "log-average";
    job.percentiles = "5,95";
    std::string opName = "reinhard", statsOut, adaptFrom;
    DisplaySettings display;
    bool noDither = false, adapt = false, meterOnly = false, scan = false;
    cl.option("--op", opName, "NAME",
              "reinhard (default), reinhard-local, drago, hable, pbr-neutral, agx, exposure, "
              "aces (the ACES 1.0 SDR output transform, as the view) or none (scene-linear "
              "x 2^exposure, unclipped, to the display/view: a config's own view such as "
              "Filmic or AgX tone-maps)");
    cl.option("--key", key, "A", "key α: the metered luminance maps to this (default 0.18)",
              {0.0, 100.0, true});
    cl.option("--exposure", exposure, "STOPS", "extra exposure in stops (default 0)",
              {-64.0, 64.0});
    cl.option("--white", job.white, "L|auto|inf",
              "reinhard's white point in scaled luminance (default auto: the largest in the "
              "image; inf: L/(1+L))");
    cl.option("--metering", job.metering, "log-average|histogram",
              "the log-average of all pixels (default), or of those between two percentiles");
    cl.option("--percentiles", job.percentiles, "LO,HI",
              "the percentile window of --metering histogram (default 5,95)");
    cl.option("--weights", job.weights, "seed|rec709",
              "luminance weights: 0.27/0.67/0.06 (default) or 0.2126/0.7152/0.0722");
    cl.option("--delta", delta, "D", "δ of the log-average (default 1e-4)", {0.0, 1.0, true});
    cl.option("--bits", job.bits, "8|16", "bits per channel of PNG/TIFF output (default 8)", 8, 16);
    cl.flag("--no-dither", noDither, "quantize 8-bit output without dithering");
    cl.option("--ocio-config", display.config, "FILE",
              "OpenColorIO config (default: $OCIO, else a built-in one: scene-linear Rec.709 in, "
              "display sRGB, views Standard and ACES)");
    cl.option("--colorspace", display.colorspace, "NAME",
              "colour space of the input (default: the config's scene_linear)");
    cl.option("--display", display.display, "NAME", "display (default: the config's default)");
    cl.option("--view", display.view, "NAME",
              "view (default: the display's default; ACES with --op aces)");
    cl.option("--look", display.look, "NAME", "look applied in scene-linear before the view");
    cl.option("--layer", job.layer, "NAME",
              "the layer or EXR part to map (default: the unnamed R,G,B,A, else the one "
              "called Combined, rgba or beauty)");
    cl.flag("--adapt", adapt,
            "eye adaptation over the sequence: adapted += (L - adapted)(1 - 0.98^(30 dt))");
    cl.option("--fps", fps, "N", "frames per second of the sequence, dt = 1/fps (default 24)",
              {0.0, 1000.0, true});
    cl.option("--stats-out", statsOut, "FILE.json",
              "write each frame's metered and adapted luminance");
    cl.option("--memory", memoryMiB, "MiB",
              "a frame whose float pixels need more than this is streamed: read strip by strip, "
              "once per metering pass and once to map, instead of whole (default 512; 0 "
              "streams every frame; the same pixels either way; reinhard-local always reads "
              "the frame whole)",
              {0.0, 1048576.0});
    cl.flag("--meter-only", meterOnly,
            "meter the frames and write --stats-out, no images (the first step of adaptation "
            "split into jobs: docs/farm.md)");
    cl.flag("--scan", scan,
            "the inputs are --meter-only statistics files: combine them in frame order, run "
            "the adaptation (--fps) and write --stats-out");
    cl.option("--adapt-from", adaptFrom, "FILE.json",
              "map each frame with the adapted luminance a --scan (or --adapt --stats-out) "
              "wrote for it: the same pictures as one --adapt run over the whole sequence");
    cl.epilog("Examples:\n  dhdr-tonemap frame.hdr.exr -o frame.png -v\n"
              "  dhdr-tonemap frame.hdr.exr --op hable --exposure 0.5 -o frame.jpg\n"
              "  dhdr-tonemap shot.####.exr --frames 1-100 --adapt -o shot.####.png\n"
              "Adaptation in separate processes (what dhdr-farm runs):\n"
              "  dhdr-tonemap shot.####.exr --frames 1-50 --meter-only --stats-out m1.json\n"
              "  dhdr-tonemap shot.####.exr --frames 51-100 --meter-only --stats-out m2.json\n"
              "  dhdr-tonemap --scan m1.json m2.json --stats-out adapted.json\n"
              "  dhdr-tonemap shot.####.exr --frames 1-50 --adapt-from adapted.json -o "
              "shot.####.png");
    cl.namesFile("--ocio-config", app::FileRole::Input);
    cl.namesFile("--adapt-from", app::FileRole::Input);
    cl.namesFile("--stats-out", app::FileRole::Output);
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-tonemap", cl);
    const int modes = int(adapt) + int(meterOnly) + int(scan) + int(!adaptFrom.empty());
    if (modes > 1) return usage("give at most one of --adapt, --meter-only, --scan, --adapt-from");
    if ((meterOnly || scan) && statsOut.empty())
        return usage(std::string(meterOnly ? "--meter-only" : "--scan") +
                     " writes its statistics to --stats-out FILE.json");
    if ((meterOnly || scan) && !cl.output().empty())
        return usage(std::string(meterOnly ? "--meter-only" : "--scan") +
                     " writes no image; give --stats-out FILE.json instead of -o");
    if (scan) {
        if (cl.inputs().empty()) return usage("--scan needs the statistics files to combine");
        if (const int status = tool.start(cl.inputs(), statsOut); status >= 0) return status;
        return app::scanStatistics(tool, cl.inputs(), fps, statsOut);
    }
    if (cl.inputs().size() != 1) return usage("give one HDR image or frame pattern");

    ToneMapParams& params = job.params;
    if (!parseToneOperator(opName, params.op))
        return usage("--op must be reinhard, reinhard-local, drago, hable, pbr-neutral, agx, "
                     "exposure, aces or none");
    if (params.op == ToneOperator::Aces && display.view.empty()) display.view = "ACES";
    params.key = key;
    params.exposure = exposure;
    LuminanceStatsParams& lum = params.metering.luminance;
    lum.delta = delta;
    if (job.weights == "seed")
        lum.weights = kSeedLuminanceWeights;
    else if (job.weights == "rec709")
        lum.weights = kRec709LuminanceWeights;
    else
        return usage("--weights must be seed or rec709");
    if (job.metering == "histogram")
        params.metering.mode = MeteringMode::Histogram;
    else if (job.metering != "log-average")
        return usage("--metering must be log-average or histogram");
    std::vector<double> window;
    if (!app::parseNumbers(job.percentiles, window, 2) || !(window[0] >= 0.0) ||
        !(window[0] < window[1]) || !(window[1] <= 100.0))
        return usage("--percentiles must be LO,HI with 0 <= LO < HI <= 100");
    params.metering.lowPercentile = window[0];
    params.metering.highPercentile = window[1];
    if (job.white == "inf")
        params.white = INFINITY;
    else if (job.white != "auto") {
        char* end = nullptr;
        params.white = std::strtod(job.white.c_str(), &end);
        if (*end != '\0' || !(params.white > 0.0) || !std::isfinite(params.white))
            return usage("--white must be a positive number, auto or inf");
    }
    if (job.bits != 8 && job.bits != 16)
        return usage("--bits: " + std::to_string(job.bits) + " is not 8 or 16");
    if (const std::string ext = app::lowerExtension(cl.output());
        job.bits == 16 && (ext == ".jpg" || ext == ".jpeg"))
        return usage("--bits 16: JPEG holds 8 bits per channel; write PNG or TIFF for 16");
    job.dither = !noDither;
    job.wholeFrameBytes = size_t(memoryMiB * 1048576.0);

    const std::string& frames = cl.frames();
    const app::FramePattern input(cl.inputs()[0]), output(cl.output());
    if (!meterOnly && input.isSequence() != output.isSequence())
        return usage("give a frame pattern for both the input and the output, or for neither");
    if (!input.isSequence() && (adapt || meterOnly || !adaptFrom.empty() || !frames.empty()))
        return usage("--adapt, --meter-only, --adapt-from and --frames need a frame pattern "
                     "(shot.####.exr)");
    if (const int status = tool.start(cl.inputs(), meterOnly ? statsOut : cl.output()); status >= 0)
        return status;
    if (std::string error; !job.display.init(display, error)) return tool.fail(error);
    tool.info("display " + job.display.describe());

    if (!input.isSequence()) {
        LuminanceStats used;
        return app::mapFrame(tool, job, input.path(0), output.path(0), nullptr, nullptr, used,
                             tool.threads())
                   ? app::kExitSuccess
                   : app::kExitFailure;
    }

    // A sequence: frames are independent except for adaptation, which is a scan over the
    // per-frame metering: meter every frame (in parallel), scan, then map every frame (in
    // parallel). Each frame runs on one thread, so the result does not depend on how many.
    std::vector<int> numbers;
    if (!frames.empty()) {
        int first = 0, last = 0;
        if (!app::parseFrameRange(frames, first, last))
            return usage(std::string("--frames must be A-B, ") + app::kFrameRangeText);
        for (int f = first; f <= last; ++f)
            numbers.push_back(f);
    } else {
        numbers = input.existingFrames();
        if (numbers.empty()) return tool.fail(input.text() + ": no frames match the pattern");
        // A gap in the sequence: adaptation would step over it as if it were one frame.
        std::string missing;
        int gaps = 0;
        for (size_t i = 1; i < numbers.size(); ++i)
            for (int f = numbers[i - 1] + 1; f < numbers[i]; ++f)
                if (++gaps <= 5) missing += (missing.empty() ? "" : ", ") + input.path(f);
        if (gaps > 0)
            tool.warn(std::to_string(gaps) + " frames missing from the sequence (" + missing +
                      (gaps > 5 ? ", …" : "") + ")" +
                      (adapt ? "; adaptation steps over them as if they were not there" : ""));
    }
    if (const int status =
            app::checkFrameOutputs(tool, cl.inputs(), meterOnly ? statsOut : cl.output(), numbers);
        status >= 0)
        return status;
    const size_t n = numbers.size();
    const std::string metering = app::meteringDescription(job);

    // --adapt-from: every frame's adapted luminance, found before anything is written.
    std::vector<double> given(n), givenMeasured(n);
    if (!adaptFrom.empty()) {
        app::SequenceStats file;
        if (std::string error; !app::readSequenceStats(adaptFrom, file, error))
            return tool.fail(error);
        if (!file.adapt)
            return tool.fail(adaptFrom + ": holds no adapted luminance (write it with --scan "
                                         "or --adapt --stats-out)");
        if (file.metering != metering)
            return tool.fail(adaptFrom + ": metered with " + file.metering +
                             ", but this run "
                             "meters with " +
                             metering);
        for (size_t i = 0; i < n; ++i) {
            const auto row =
                std::find_if(file.frames.begin(), file.frames.end(),
                             [&](const app::FrameLuminance& f) { return f.frame == numbers[i]; });
            if (row == file.frames.end())
                return tool.fail(adaptFrom + ": has no frame " + std::to_string(numbers[i]));
            given[i] = row->adapted;
            givenMeasured[i] = row->logAverage;
        }
    }
    const int workers = tool.threads() > 0 ? tool.threads() : 0;
    const auto start = std::chrono::steady_clock::now();

    std::vector<LuminanceStats> metered(n);
    std::vector<double> measured(n); // each frame's own metering, before adaptation
    std::vector<char> failed(n, 0);
    // The metering pass reads every frame, and the mapping pass reads it again: keeping frames
    // between the passes (as half floats) was measured no faster and took 1.7 GB for 100
    // frames of 1080p.
    if (adapt || meterOnly) {
        OIIO::parallel_for(
            int64_t(0), int64_t(n),
            [&](int64_t i) {
                if (!app::meterFrame(tool, job, input.path(numbers[size_t(i)]), metered[size_t(i)],
                                     1))
                    failed[size_t(i)] = 1;
            },
            perItem(workers));
        // Nothing is written when any frame cannot be read.
        if (std::find(failed.begin(), failed.end(), 1) != failed.end()) return app::kExitFailure;
        for (size_t i = 0; i < n; ++i)
            measured[i] = metered[i].logAverage;
        if (meterOnly) {
            app::SequenceStats stats;
            stats.fps = fps;
            stats.metering = metering;
            for (size_t i = 0; i < n; ++i)
                stats.frames.push_back(
                    {numbers[i], input.path(numbers[i]), measured[i], measured[i]});
            tool.info("metered " + std::to_string(n) + " frames");
            return tool.writeText(app::toJson(stats), statsOut) ? app::kExitSuccess
                                                                : app::kExitFailure;
        }
        AdaptationParams ap;
        ap.fps = fps;
        const std::vector<double> adapted = adaptLuminance(measured, ap);
        for (size_t i = 0; i < n; ++i)
            metered[i].logAverage = adapted[i];
    }

    std::vector<LuminanceStats> used(n); // the metering each frame was mapped with
    {
        SequenceProgress progress(tool, n);
        OIIO::parallel_for(
            int64_t(0), int64_t(n),
            [&](int64_t i) {
                const int f = numbers[size_t(i)];
                if (!app::mapFrame(tool, job, input.path(f), output.path(f),
                                   adapt ? &metered[size_t(i)] : nullptr,
                                   adaptFrom.empty() ? nullptr : &given[size_t(i)], used[size_t(i)],
                                   1))
                    failed[size_t(i)] = 1;
                progress.frameDone();
            },
            perItem(workers));
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char line[160];
    std::snprintf(line, sizeof line, "%zu frames in %.2f s (%.1f frames/s)", n, seconds,
                  double(n) / seconds);
    tool.info(line);
    const size_t failures = size_t(std::count(failed.begin(), failed.end(), 1));
    if (failures > 0)
        return tool.fail(std::to_string(failures) + " of " + std::to_string(n) +
                         " frames failed (see above)");

    if (!statsOut.empty()) {
        app::SequenceStats stats;
        stats.fps = fps;
        stats.adapt = adapt || !adaptFrom.empty();
        stats.metering = metering;
        // Without adaptation, each frame is mapped with its own metering.
        for (size_t i = 0; i < n; ++i)
            stats.frames.push_back({numbers[i], input.path(numbers[i]),
                                    adapt               ? measured[i]
                                    : adaptFrom.empty() ? used[i].logAverage
                                                        : givenMeasured[i],
                                    used[i].logAverage});
        if (!tool.writeText(app::toJson(stats), statsOut)) return app::kExitFailure;
    }
    return app::kExitSuccess;
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-tonemap", [&] { return run(argc, argv); });
}
