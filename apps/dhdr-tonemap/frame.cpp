#include "frame.h"

#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <dhdr/io/layers.h>
#include <dhdr/io/sanitize.h>
#include <dhdr/io/strip_pipeline.h>
#include <dhdr/tonemap/metering.h>
#include <dhdr/tonemap/quantize.h>
#include <filesystem>
#include <vector>

namespace dhdr::app {

namespace {

// Rows the display transform, quantization and encoding work on at a time.
constexpr int kStripRows = 64;
// libpng's PNG_FILTER_NONE.
constexpr int kPngFilterNone = 0x08;

// Replaces what a display cannot show in `hdr` (the whole frame or a strip of it) and brings
// it to scene-linear, where metering and operators work. A display shows no negative light:
// negative colour goes with NaN and Inf, in one warning; alpha keeps its negatives.
bool toSceneLinear(const FrameJob& job, OIIO::ImageBuf& hdr, NonFiniteCount& replaced,
                   int nthreads) {
    OIIO::ROI colour = hdr.roi(), alpha = hdr.roi();
    colour.chend = 3;
    alpha.chbegin = 3;
    alpha.chend = std::min(hdr.nchannels(), 4);
    replaced += replaceNonFinite(hdr, colour, nthreads, true);
    if (alpha.chend > alpha.chbegin) replaced += replaceNonFinite(hdr, alpha, nthreads, false);
    return job.display.toSceneLinear(hdr, {}, nthreads);
}

void reportInput(const Tool& tool, const FrameJob& job, const std::string& path,
                 const OIIO::ImageSpec& spec, bool surface, const NonFiniteCount& replaced) {
    if (!surface) tool.warnNoSurface(path);
    tool.reportNonFinite(path, replaced, true);
    if (const std::string from = job.display.inputColorSpace(spec); !from.empty())
        tool.info(path + ": display-encoded (the file says sRGB): decoded from '" + from + "'");
}

// Reads the colour of `path` (its layer by name) whole, in scene-linear (warning when `warn`).
bool readSceneLinear(const Tool& tool, const FrameJob& job, const std::string& path,
                     OIIO::ImageBuf& hdr, bool warn, int nthreads) {
    std::vector<OIIO::TypeDesc> formats;
    if (!tool.readColour(path, job.layer, false, hdr, formats, nthreads)) return false;
    const bool surface = hasSurface(hdr);
    NonFiniteCount replaced;
    if (!toSceneLinear(job, hdr, replaced, nthreads)) return false;
    if (warn) reportInput(tool, job, path, hdr.spec(), surface, replaced);
    return true;
}

// A frame read strip by strip, each strip as readSceneLinear gives the whole: what a frame
// too large for FrameJob::wholeFrameBytes is mapped from. Non-finite colour is replaced value
// by value, so a strip gives what the whole frame would (docs/tools.md).
class SceneLinearStrips {
public:
    SceneLinearStrips(const Tool& tool, const FrameJob& job, std::string path, int nthreads)
        : m_tool(tool), m_job(job), m_path(std::move(path)), m_nthreads(nthreads) {}
    bool open() { return m_tool.openColour(m_path, m_job.layer, false, m_reader); }
    const OIIO::ImageSpec& spec() const { return m_reader.spec(); }
    const std::string& path() const { return m_path; }
    const Tool& tool() const { return m_tool; }
    // Rows [ybegin, yend) into `strip`; counts what it replaced when `count`. Called by one
    // thread at a time (a StripPipeline's reads).
    bool read(int ybegin, int yend, bool count, OIIO::ImageBuf& strip, std::string& error) {
        if (!m_reader.read(ybegin, yend, strip, error)) return false;
        if (count) m_surface = m_surface || hasSurface(strip);
        NonFiniteCount replaced;
        if (!toSceneLinear(m_job, strip, replaced, m_nthreads)) {
            error = strip.geterror();
            return false;
        }
        if (count) m_replaced += replaced;
        return true;
    }
    // The frame as a StripPipeline's input, counting when `count`.
    StripInput input(bool count) {
        return {[this, count](int y0, int y1, OIIO::ImageBuf& strip, std::string& error) {
                    return read(y0, y1, count, strip, error);
                },
                m_path,
                {}};
    }
    void report() const {
        reportInput(m_tool, m_job, m_path, m_reader.spec(), m_surface, m_replaced);
    }

private:
    const Tool& m_tool;
    const FrameJob& m_job;
    std::string m_path;
    int m_nthreads;
    ColourStripReader m_reader;
    bool m_surface = false;
    NonFiniteCount m_replaced;
};

// Whether the frame is streamed: its float pixels pass the budget and the operator works
// pixel by pixel once metered.
bool streamed(const FrameJob& job, const OIIO::ImageSpec& spec) {
    return job.params.op != ToneOperator::ReinhardLocal &&
           size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels) * sizeof(float) >
               job.wholeFrameBytes;
}

// Meters every row of `frame` in the passes the metering needs.
bool meterStrips(SceneLinearStrips& frame, const MeteringParams& params, LuminanceStats& stats,
                 int nthreads) {
    MeteringAccumulator accumulator(params);
    StripPipelineParams strips;
    strips.rows = kStripRows;
    strips.nthreads = nthreads;
    do {
        StripPipeline pass(OIIO::get_roi(frame.spec()), strips);
        pass.addInput(frame.input(false));
        const bool metered = pass.run([&](StripContext& strip) {
            if (accumulator.add(*strip.inputs[0], {}, nthreads)) return true;
            strip.error = frame.path() + ": " + strip.inputs[0]->geterror();
            return false;
        });
        if (!metered) {
            frame.tool().fail(pass.error());
            return false;
        }
        accumulator.endPass();
    } while (accumulator.needsAnotherPass());
    stats = accumulator.result();
    return true;
}

// The frame a thread works on, kept from frame to frame of a sequence so that its pixels are
// overwritten rather than allocated again (page faults were a tenth of a sequence's time).
OIIO::ImageBuf& threadFrame() {
    thread_local OIIO::ImageBuf frame;
    return frame;
}

// The image a display is sent: at most R, G, B and alpha of `hdr`, in `type`, with `hdr`'s
// metadata.
OIIO::ImageSpec displaySpec(const OIIO::ImageSpec& hdr, OIIO::TypeDesc type) {
    const int nch = std::min(hdr.nchannels, 4);
    OIIO::ImageSpec spec = hdr;
    spec.nchannels = nch;
    spec.channelnames = {"R", "G", "B", "A"};
    spec.channelnames.resize(size_t(nch));
    spec.alpha_channel = nch == 4 ? 3 : -1;
    spec.z_channel = -1;
    spec.channelformats.clear();
    spec.set_format(type);
    return spec;
}

} // namespace

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    return ext;
}

bool meterFrame(const Tool& tool, const FrameJob& job, const std::string& in, LuminanceStats& stats,
                int nthreads) {
    SceneLinearStrips strips(tool, job, in, nthreads);
    if (!strips.open()) return false;
    if (streamed(job, strips.spec()))
        return meterStrips(strips, job.params.metering, stats, nthreads);
    OIIO::ImageBuf& hdr = threadFrame();
    return readSceneLinear(tool, job, in, hdr, false, nthreads) &&
           meter(stats, hdr, job.params.metering, {}, nthreads);
}

// Meters `in` (or uses `given`; or meters it and maps it with the log-average `adapted`),
// tone-maps it and writes `out`; `used` receives the metering.
bool mapFrame(const Tool& tool, const FrameJob& job, const std::string& in, const std::string& out,
              const LuminanceStats* given, const double* adapted, LuminanceStats& used,
              int nthreads) {
    SceneLinearStrips strips(tool, job, in, nthreads);
    if (!strips.open()) return false;
    const bool streaming = streamed(job, strips.spec());
    OIIO::ImageBuf& hdr = threadFrame();
    if (streaming) {
        hdr.reset();
    } else if (!readSceneLinear(tool, job, in, hdr, true, nthreads)) {
        return false;
    }
    ToneMapParams params = job.params;
    if (given) {
        used = *given;
    } else {
        if (streaming ? !meterStrips(strips, params.metering, used, nthreads)
                      : !meter(used, hdr, params.metering, {}, nthreads))
            return false;
        if (adapted) used.logAverage = *adapted;
    }
    params.stats = &used;
    char line[320];
    std::snprintf(line, sizeof line, "%s: %s luminance %.6g (largest %.6g)", in.c_str(),
                  given || adapted ? "adapted" : job.metering.c_str(), used.logAverage,
                  used.maxLuminance);
    tool.info(line);
    // In place: the frame is not needed in scene-linear after this.
    if (!streaming && !toneMap(hdr, hdr, params, {}, nthreads)) {
        tool.fail(in + ": " + hdr.geterror());
        return false;
    }

    // Every format gets the same display-referred values; only their quantization differs.
    const std::string ext = lowerExtension(out);
    const bool exr = ext == ".exr";
    const bool sixteen = job.bits == 16;
    const OIIO::TypeDesc type = exr       ? OIIO::TypeDesc::HALF
                                : sixteen ? OIIO::TypeDesc::UINT16
                                          : OIIO::TypeDesc::UINT8;
    OIIO::ImageSpec spec = displaySpec(streaming ? strips.spec() : hdr.spec(), type);
    // Strings, which every format keeps (PNG drops numeric attributes).
    spec.attribute("dhdr:toneMap", toneOperatorName(params.op));
    std::snprintf(line, sizeof line,
                  "key %g, exposure %g, white %s, weights %s, delta %g, metering %s%s%s -> %.6g",
                  params.key, params.exposure, job.white.c_str(), job.weights.c_str(),
                  params.metering.luminance.delta, job.metering.c_str(),
                  job.metering == "histogram" ? " " : "",
                  job.metering == "histogram" ? job.percentiles.c_str() : "", used.logAverage);
    spec.attribute("dhdr:toneMapParameters", line);
    spec.attribute("dhdr:source", in);
    spec.attribute("dhdr:display", job.display.describe());
    // The input's "Linear" would make PNG declare a gamma of 1 to viewers.
    spec.attribute("oiio:ColorSpace", job.display.outputColorSpace());
    QuantizeParams quantizing;
    quantizing.dither = type == OIIO::TypeDesc::UINT8 && job.dither;
    if (quantizing.dither) {
        spec.attribute("dhdr:dither", "ordered, 8x8 Bayer");
        // Dithered pixels defeat PNG's row predictors: unfiltered rows compress as well or
        // better and encode three times faster (docs/tonemap.md).
        spec.attribute("png:filter", kPngFilterNone);
    }

    AtomicOutput file(tool, out);
    if (!file.open(spec, {type})) return false;
    // EXR gets floats that OpenImageIO converts to half; the others their integer pixels.
    const OIIO::TypeDesc buffer = exr ? OIIO::TypeDesc::FLOAT : type;
    StripPipelineParams streamingParams;
    streamingParams.rows = kStripRows;
    streamingParams.writeBehind = nthreads != 1;
    streamingParams.nthreads = nthreads;
    StripPipeline pipeline(OIIO::get_roi(spec), streamingParams);
    if (streaming) pipeline.addInput(strips.input(true));
    pipeline.setOutput(file.file());
    const bool written = pipeline.run([&](StripContext& strip) {
        if (streaming && !toneMap(*strip.inputs[0], *strip.inputs[0], params, {}, nthreads)) {
            strip.error = in + ": " + strip.inputs[0]->geterror();
            return false;
        }
        OIIO::ImageBuf& src = streaming ? *strip.inputs[0] : hdr;
        job.display.toDisplay(src, strip.rows, nthreads);
        OIIO::ImageSpec rows(strip.rows.width(), strip.rows.height(), spec.nchannels, buffer);
        rows.x = strip.rows.xbegin;
        rows.y = strip.rows.ybegin;
        OIIO::ImageBuf& dst = *strip.output;
        if (dst.spec().width != rows.width || dst.spec().height != rows.height ||
            dst.spec().format != buffer)
            dst.reset(rows);
        dst.set_origin(rows.x, rows.y);
        const bool done =
            exr ? OIIO::ImageBufAlgo::copy(dst, src, OIIO::TypeUnknown, strip.rows, nthreads)
                : quantize(dst, src, quantizing, strip.rows, nthreads);
        if (!done) strip.error = out + ": " + dst.geterror();
        return done;
    });
    if (!written) {
        tool.fail(pipeline.error());
        return false;
    }
    if (streaming) strips.report();
    return file.commit();
}

// Everything that decides a frame's metered luminance, so that statistics metered one way
// are not combined with, or applied to, frames metered another.
std::string meteringDescription(const FrameJob& job) {
    const MeteringParams& m = job.params.metering;
    char text[200];
    std::snprintf(text, sizeof text, "%s%s%s, weights %s, delta %.17g, layer '%s'",
                  job.metering.c_str(), m.mode == MeteringMode::Histogram ? " " : "",
                  m.mode == MeteringMode::Histogram ? job.percentiles.c_str() : "",
                  job.weights.c_str(), m.luminance.delta, job.layer.c_str());
    return text;
}

} // namespace dhdr::app
