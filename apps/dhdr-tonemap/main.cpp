// dhdr-tonemap: linear HDR in, a display image out; one frame or a sequence (docs/tools.md).
#include "../common/frames.h"
#include "../common/param_options.h"
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
#include <fstream>
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

// What the command line says besides the frame job.
struct Options {
    AdaptationParams adaptation; // --fps
    double memoryMiB = 512.0;
    std::string statsOut, adaptFrom;
    DisplaySettings display;
    bool noDither = false, adapt = false, meterOnly = false, scan = false;
    std::string scanList; // --scan's files, one a line
};

void declareOptions(app::CommandLine& cl, Options& o, FrameJob& job) {
    app::addParamOptions(cl, job.params, kToneMapChoiceTable);
    app::addParamOptions(cl, job.params, kToneMapFloatTable);
    cl.option("--white", job.white, "L|auto|inf",
              "reinhard's white point in scaled luminance (default auto: the largest in the "
              "image; inf: L/(1+L))");
    cl.option("--metering", job.metering, "log-average|histogram",
              "the log-average of all pixels (default), or of those between two percentiles");
    cl.option("--percentiles", job.percentiles, "LO,HI",
              "the percentile window of --metering histogram");
    cl.option("--weights", job.weights, "seed|rec709",
              "luminance weights: 0.27/0.67/0.06 (default) or 0.2126/0.7152/0.0722");
    app::addParamOptions(cl, job.params.metering.luminance, kLuminanceFloatTable);
    cl.option("--bits", job.bits, "8|16", "bits per channel of PNG/TIFF output", 8, 16);
    cl.flag("--no-dither", o.noDither, "quantize 8-bit output without dithering");
    cl.option("--png-writer", job.pngWriter, "dhdr|oiio",
              "PNG through dhdr's writer, its deflate on every thread (default), or through "
              "OpenImageIO's (the reference: the same chunks and pixels, slower)");
    cl.option("--ocio-config", o.display.config, "FILE",
              "OpenColorIO config (default: $OCIO, else a built-in one: scene-linear Rec.709 in, "
              "display sRGB, views Standard and ACES)");
    cl.option("--colorspace", o.display.colorspace, "NAME",
              "colour space of the input (default: the config's scene_linear)");
    cl.option("--display", o.display.display, "NAME", "display (default: the config's default)");
    cl.option("--view", o.display.view, "NAME",
              "view (default: the display's default; ACES with --op aces)");
    cl.option("--look", o.display.look, "NAME", "look applied in scene-linear before the view");
    cl.option("--layer", job.layer, "NAME",
              "the layer or EXR part to map (default: the unnamed R,G,B,A, else the one "
              "called Combined, rgba or beauty)");
    cl.flag("--adapt", o.adapt,
            "eye adaptation over the sequence: adapted += (L - adapted)(1 - R^(S dt)), dt = "
            "1/fps (--adapt-rate R, --adapt-speed S)");
    app::addParamOptions(cl, o.adaptation, kAdaptationFloatTable);
    cl.option("--stats-out", o.statsOut, "FILE.json",
              "write each frame's metered and adapted luminance");
    cl.option("--memory", o.memoryMiB, "MiB",
              "a frame whose float pixels need more than this is streamed: read strip by strip, "
              "once per metering pass and once to map, instead of whole (0 streams every frame; "
              "the same pixels either way; reinhard-local always reads the frame whole)",
              {0.0, 1048576.0});
    cl.flag("--meter-only", o.meterOnly,
            "meter the frames and write --stats-out, no images (the first step of adaptation "
            "split into jobs: docs/farm.md)");
    cl.flag("--scan", o.scan,
            "the inputs are --meter-only statistics files: combine them in frame order, run "
            "the adaptation (--fps) and write --stats-out");
    cl.option("--scan-list", o.scanList, "FILE",
              "with --scan: a text file naming statistics files to combine, one a line (more "
              "than a command line holds: dhdr-farm's scan of thousands of chunks)");
    cl.option("--adapt-from", o.adaptFrom, "FILE.json",
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
    cl.namesFile("--scan-list", app::FileRole::Input);
    cl.namesFile("--stats-out", app::FileRole::Output);
}

// The usage errors of the modes (--adapt, --meter-only, --scan, --adapt-from). Returns -1 to
// go on, else the exit status.
int checkModes(const app::CommandLine& cl, const Options& o) {
    const int modes = int(o.adapt) + int(o.meterOnly) + int(o.scan) + int(!o.adaptFrom.empty());
    if (modes > 1) return usage("give at most one of --adapt, --meter-only, --scan, --adapt-from");
    if ((o.meterOnly || o.scan) && o.statsOut.empty())
        return usage(std::string(o.meterOnly ? "--meter-only" : "--scan") +
                     " writes its statistics to --stats-out FILE.json");
    if (!o.scanList.empty() && !o.scan) return usage("--scan-list goes with --scan");
    if ((o.meterOnly || o.scan) && !cl.output().empty())
        return usage(std::string(o.meterOnly ? "--meter-only" : "--scan") +
                     " writes no image; give --stats-out FILE.json instead of -o");
    return -1;
}

// The operator and metering options into `job`. Returns -1 to go on, else the exit status.
int parseJob(const app::CommandLine& cl, Options& o, FrameJob& job) {
    ToneMapParams& params = job.params;
    if (params.op == ToneOperator::Aces && o.display.view.empty()) o.display.view = "ACES";
    LuminanceStatsParams& lum = params.metering.luminance;
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
    if (app::parseNumbers(job.percentiles, window, 2)) {
        params.metering.lowPercentile = window[0];
        params.metering.highPercentile = window[1];
    } else {
        params.metering.highPercentile = -1.0; // not LO,HI: no window, refused below
    }
    if (const std::string e = percentilesProblem(params.metering, Spelling::Option); !e.empty())
        return usage(e);
    if (std::string e; !parseWhite(job.white, params.white, Spelling::Option, e)) return usage(e);
    if (job.bits != 8 && job.bits != 16)
        return usage("--bits: " + std::to_string(job.bits) + " is not 8 or 16");
    if (const std::string ext = app::lowerExtension(cl.output());
        job.bits == 16 && (ext == ".jpg" || ext == ".jpeg"))
        return usage("--bits 16: JPEG holds 8 bits per channel; write PNG or TIFF for 16");
    if (job.pngWriter != "dhdr" && job.pngWriter != "oiio")
        return usage("--png-writer must be dhdr or oiio");
    job.dither = !o.noDither;
    job.wholeFrameBytes = size_t(o.memoryMiB * 1048576.0);
    return -1;
}

// The frame numbers of a sequence: --frames, else those on disk (warning about gaps). Returns
// -1 to go on, else the exit status.
int sequenceNumbers(const app::Tool& tool, const std::string& frames,
                    const app::FramePattern& input, bool adapt, std::vector<int>& numbers) {
    if (!frames.empty()) {
        int first = 0, last = 0;
        if (!app::parseFrameRange(frames, first, last))
            return usage("--frames must be A-B, " + app::frameRangeText());
        for (int f = first; f <= last; ++f)
            numbers.push_back(f);
        return -1;
    }
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
    return -1;
}

// A sequence's run: every frame's metering, adaptation and mapping.
struct Sequence {
    Sequence(const std::string& in, const std::string& out) : input(in), output(out) {}
    app::FramePattern input, output;
    std::vector<int> numbers;
    std::string metering;                     // meteringDescription
    std::vector<double> given, givenMeasured; // --adapt-from's adapted and measured luminance
    std::vector<LuminanceStats> metered;
    std::vector<double> measured;     // each frame's own metering, before adaptation
    std::vector<LuminanceStats> used; // the metering each frame was mapped with
    std::vector<char> failed;
};

// --adapt-from: every frame's adapted luminance, found before anything is written.
bool readAdaptFrom(const app::Tool& tool, const std::string& adaptFrom, Sequence& seq) {
    app::SequenceStats file;
    if (std::string error; !app::readSequenceStats(adaptFrom, file, error))
        return tool.fail(error), false;
    if (!file.adapt)
        return tool.fail(adaptFrom + ": holds no adapted luminance (write it with --scan "
                                     "or --adapt --stats-out)"),
               false;
    if (file.metering != seq.metering)
        return tool.fail(adaptFrom + ": metered with " + file.metering +
                         ", but this run "
                         "meters with " +
                         seq.metering),
               false;
    for (size_t i = 0; i < seq.numbers.size(); ++i) {
        const auto row =
            std::find_if(file.frames.begin(), file.frames.end(),
                         [&](const app::FrameLuminance& f) { return f.frame == seq.numbers[i]; });
        if (row == file.frames.end())
            return tool.fail(adaptFrom + ": has no frame " + std::to_string(seq.numbers[i])), false;
        seq.given[i] = row->adapted;
        seq.givenMeasured[i] = row->logAverage;
    }
    return true;
}

// Meters every frame (in parallel; each frame on one thread). False when any cannot be read.
bool meterSequence(const app::Tool& tool, const FrameJob& job, Sequence& seq, int workers) {
    const size_t n = seq.numbers.size();
    OIIO::parallel_for(
        int64_t(0), int64_t(n),
        [&](int64_t i) {
            if (!app::meterFrame(tool, job, seq.input.path(seq.numbers[size_t(i)]),
                                 seq.metered[size_t(i)], 1))
                seq.failed[size_t(i)] = 1;
        },
        perItem(workers));
    if (std::find(seq.failed.begin(), seq.failed.end(), 1) != seq.failed.end()) return false;
    for (size_t i = 0; i < n; ++i)
        seq.measured[i] = seq.metered[i].logAverage;
    return true;
}

// Maps every frame (in parallel; each frame on one thread, so the result does not depend on
// how many).
void mapSequence(const app::Tool& tool, const FrameJob& job, const Options& o, Sequence& seq,
                 int workers) {
    SequenceProgress progress(tool, seq.numbers.size());
    OIIO::parallel_for(
        int64_t(0), int64_t(seq.numbers.size()),
        [&](int64_t i) {
            const int f = seq.numbers[size_t(i)];
            if (!app::mapFrame(tool, job, seq.input.path(f), seq.output.path(f),
                               o.adapt ? &seq.metered[size_t(i)] : nullptr,
                               o.adaptFrom.empty() ? nullptr : &seq.given[size_t(i)],
                               seq.used[size_t(i)], 1))
                seq.failed[size_t(i)] = 1;
            progress.frameDone();
        },
        perItem(workers));
}

// --stats-out of a run that mapped: each frame's measured and used luminance.
bool writeStats(const app::Tool& tool, const Options& o, const Sequence& seq) {
    app::SequenceStats stats;
    stats.fps = o.adaptation.fps;
    stats.adapt = o.adapt || !o.adaptFrom.empty();
    stats.metering = seq.metering;
    // Without adaptation, each frame is mapped with its own metering.
    for (size_t i = 0; i < seq.numbers.size(); ++i)
        stats.frames.push_back({seq.numbers[i], seq.input.path(seq.numbers[i]),
                                o.adapt               ? seq.measured[i]
                                : o.adaptFrom.empty() ? seq.used[i].logAverage
                                                      : seq.givenMeasured[i],
                                seq.used[i].logAverage});
    return tool.writeText(app::toJson(stats), o.statsOut);
}

// A sequence: frames are independent except for adaptation, which is a scan over the
// per-frame metering: meter every frame (in parallel), scan, then map every frame (in
// parallel).
int runSequence(const app::Tool& tool, const app::CommandLine& cl, const FrameJob& job,
                const Options& o, Sequence& seq) {
    if (const int status = sequenceNumbers(tool, cl.frames(), seq.input, o.adapt, seq.numbers);
        status >= 0)
        return status;
    if (const int status = app::checkFrameOutputs(
            tool, cl.inputs(), o.meterOnly ? o.statsOut : cl.output(), seq.numbers);
        status >= 0)
        return status;
    const size_t n = seq.numbers.size();
    seq.metering = app::meteringDescription(job);
    seq.given.assign(n, 0.0);
    seq.givenMeasured.assign(n, 0.0);
    if (!o.adaptFrom.empty() && !readAdaptFrom(tool, o.adaptFrom, seq)) return app::kExitFailure;
    const int workers = tool.threads() > 0 ? tool.threads() : 0;
    const auto start = std::chrono::steady_clock::now();
    seq.metered.assign(n, LuminanceStats{});
    seq.measured.assign(n, 0.0);
    seq.failed.assign(n, 0);
    // The metering pass reads every frame, and the mapping pass reads it again: keeping frames
    // between the passes (as half floats) was measured no faster and took 1.7 GB for 100
    // frames of 1080p.
    if (o.adapt || o.meterOnly) {
        // Nothing is written when any frame cannot be read.
        if (!meterSequence(tool, job, seq, workers)) return app::kExitFailure;
        if (o.meterOnly) {
            app::SequenceStats stats;
            stats.fps = o.adaptation.fps;
            stats.metering = seq.metering;
            for (size_t i = 0; i < n; ++i)
                stats.frames.push_back({seq.numbers[i], seq.input.path(seq.numbers[i]),
                                        seq.measured[i], seq.measured[i]});
            tool.info("metered " + std::to_string(n) + " frames");
            return tool.writeText(app::toJson(stats), o.statsOut) ? app::kExitSuccess
                                                                  : app::kExitFailure;
        }
        const std::vector<double> adapted = adaptLuminance(seq.measured, o.adaptation);
        for (size_t i = 0; i < n; ++i)
            seq.metered[i].logAverage = adapted[i];
    }
    seq.used.assign(n, LuminanceStats{});
    mapSequence(tool, job, o, seq, workers);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char line[160];
    std::snprintf(line, sizeof line, "%zu frames in %.2f s (%.1f frames/s)", n, seconds,
                  double(n) / seconds);
    tool.info(line);
    const size_t failures = size_t(std::count(seq.failed.begin(), seq.failed.end(), 1));
    if (failures > 0)
        return tool.fail(std::to_string(failures) + " of " + std::to_string(n) +
                         " frames failed (see above)");
    if (!o.statsOut.empty() && !writeStats(tool, o, seq)) return app::kExitFailure;
    return app::kExitSuccess;
}

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
    FrameJob job;
    job.white = "auto";
    job.weights = "seed";
    job.metering = "log-average";
    job.percentiles = "5,95";
    Options o;
    declareOptions(cl, o, job);
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-tonemap", cl);
    if (const int status = checkModes(cl, o); status >= 0) return status;
    if (o.scan) {
        std::vector<std::string> files = cl.inputs();
        if (!o.scanList.empty()) {
            std::ifstream list(o.scanList);
            if (!list) return tool.fail(o.scanList + ": cannot be read");
            for (std::string line; std::getline(list, line);) {
                if (!line.empty() && line.back() == '\r') line.pop_back();
                if (!line.empty()) files.push_back(line);
            }
            if (list.bad()) return tool.fail(o.scanList + ": cannot be read");
        }
        if (files.empty()) return usage("--scan needs the statistics files to combine");
        if (const int status = tool.start(files, o.statsOut); status >= 0) return status;
        return app::scanStatistics(tool, files, o.adaptation, o.statsOut);
    }
    if (cl.inputs().size() != 1) return usage("give one HDR image or frame pattern");
    if (const int status = parseJob(cl, o, job); status >= 0) return status;

    Sequence seq(cl.inputs()[0], cl.output());
    const app::FramePattern& input = seq.input;
    if (!o.meterOnly && input.isSequence() != seq.output.isSequence())
        return usage("give a frame pattern for both the input and the output, or for neither");
    if (!input.isSequence() &&
        (o.adapt || o.meterOnly || !o.adaptFrom.empty() || !cl.frames().empty()))
        return usage("--adapt, --meter-only, --adapt-from and --frames need a frame pattern "
                     "(shot.####.exr)");
    if (const int status = tool.start(cl.inputs(), o.meterOnly ? o.statsOut : cl.output());
        status >= 0)
        return status;
    if (std::string error; !job.display.init(o.display, error)) return tool.fail(error);
    tool.info("display " + job.display.describe());
    if (input.isSequence()) return runSequence(tool, cl, job, o, seq);
    LuminanceStats used;
    return app::mapFrame(tool, job, input.path(0), seq.output.path(0), nullptr, nullptr, used,
                         tool.threads())
               ? app::kExitSuccess
               : app::kExitFailure;
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-tonemap", [&] { return run(argc, argv); });
}
