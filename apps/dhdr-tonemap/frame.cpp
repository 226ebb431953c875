#include "frame.h"

#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <dhdr/io/layers.h>
#include <dhdr/io/png_writer.h>
#include <dhdr/io/sanitize.h>
#include <dhdr/io/strip_pipeline.h>
#include <dhdr/tonemap/frame_recipe.h>
#include <dhdr/tonemap/metering.h>
#include <filesystem>
#include <thread>
#include <vector>

namespace dhdr::app {

namespace {

// Rows the display transform, quantization and encoding work on at a time.
constexpr int kStripRows = 64;
// libpng's PNG_FILTER_NONE.
constexpr int kPngFilterNone = 0x08;

// Replaces what a display cannot show in `hdr` (the whole frame or a strip of it) and brings
// it to scene-linear, where metering and operators work (prepareFrame).
bool toSceneLinear(const FrameJob& job, OIIO::ImageBuf& hdr, NonFiniteCount& replaced,
                   int nthreads) {
    return prepareFrame(hdr, hdr, job.display, &replaced, {}, nthreads);
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

namespace {

// The header of the display image of `hdr`: what it was mapped with, from where, for which
// display. Strings, which every format keeps (PNG drops numeric attributes).
OIIO::ImageSpec outputSpec(const FrameJob& job, const std::string& in, const OIIO::ImageSpec& hdr,
                           const FrameRecipe& recipe, OIIO::TypeDesc type,
                           const LuminanceStats& used) {
    OIIO::ImageSpec spec = displaySpec(hdr, type);
    const ToneMapParams& params = recipe.toneMap;
    spec.attribute("dhdr:toneMap", toneOperatorName(params.op));
    char line[320];
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
    if (type == OIIO::TypeDesc::UINT8 && recipe.dither) {
        spec.attribute("dhdr:dither", "ordered, 8x8 Bayer");
        // Dithered pixels defeat PNG's row predictors: unfiltered rows compress as well or
        // better and encode three times faster (docs/tonemap.md).
        spec.attribute("png:filter", kPngFilterNone);
    }
    return spec;
}

// Maps and encodes the rows of one strip into strip.output: from `hdr` mapped already, or
// from the strip `strips` read (toneMapFrame).
bool encodeStrip(StripContext& strip, const std::string& in, const std::string& out,
                 const OIIO::ImageSpec& spec, const FrameRecipe& recipe, const OIIO::ImageBuf& hdr,
                 bool streaming, int nthreads) {
    // EXR gets floats that OpenImageIO converts to half; the others their integer pixels.
    OIIO::ImageSpec rows(strip.rows.width(), strip.rows.height(), spec.nchannels, recipe.type);
    rows.x = strip.rows.xbegin;
    rows.y = strip.rows.ybegin;
    OIIO::ImageBuf& dst = *strip.output;
    if (dst.spec().width != rows.width || dst.spec().height != rows.height ||
        dst.spec().format != recipe.type)
        dst.reset(rows);
    dst.set_origin(rows.x, rows.y);
    if (streaming && !toneMapFrame(dst, *strip.inputs[0], recipe, strip.rows, nthreads)) {
        strip.error = in + ": " + dst.geterror();
        return false;
    }
    if (!streaming && !encodeFrame(dst, hdr, recipe, strip.rows, nthreads)) {
        strip.error = out + ": " + dst.geterror();
        return false;
    }
    return true;
}

StripPipelineParams displayStrips(int nthreads, bool writeBehind) {
    StripPipelineParams params;
    params.rows = kStripRows;
    params.writeBehind = writeBehind && nthreads != 1;
    params.nthreads = nthreads;
    return params;
}

// Writes `out` a strip at a time through OpenImageIO: each strip of `hdr` (mapped already)
// encoded, or with `strips` each strip read, mapped and encoded.
bool writeDisplay(const Tool& tool, const std::string& in, const std::string& out,
                  const OIIO::ImageSpec& spec, const FrameRecipe& recipe, const OIIO::ImageBuf& hdr,
                  SceneLinearStrips* strips, int nthreads) {
    AtomicOutput file(tool, out);
    if (!file.open(spec, {spec.format})) return false;
    StripPipeline pipeline(OIIO::get_roi(spec), displayStrips(nthreads, true));
    if (strips) pipeline.addInput(strips->input(true));
    pipeline.setOutput(file.file());
    if (!pipeline.run([&](StripContext& strip) {
            return encodeStrip(strip, in, out, spec, recipe, hdr, strips != nullptr, nthreads);
        })) {
        tool.fail(pipeline.error());
        return false;
    }
    if (strips) strips->report();
    return file.commit();
}

// As writeDisplay, through dhdr's PNG writer: the same chunks and pixels as OpenImageIO's,
// its deflate spread over the threads (png_writer.h).
bool writePng(const Tool& tool, const std::string& in, const std::string& out, OIIO::ImageSpec spec,
              const FrameRecipe& recipe, const OIIO::ImageBuf& hdr, SceneLinearStrips* strips,
              int nthreads) {
    // What ImageFileOutput gives OpenImageIO (tool.cpp's outputOptions; one image, flat).
    spec.attribute("Software", tool.name() + " (dhdr " DHDR_VERSION ")");
    spec.erase_attribute("oiio:subimages");
    PngFileWriter file(out);
    PngWriteOptions options;
    options.nthreads = nthreads > 0 ? nthreads : int(std::thread::hardware_concurrency());
    // A frame held whole is deflated whole (libdeflate), a streamed one in groups of rows
    // (zlib): chosen by size, never by threads, so that the bytes do not depend on them.
    options.whole = !strips;
    if (!file.open(spec, options)) return tool.fail(file.geterror()), false;
    StripPipeline pipeline(OIIO::get_roi(spec), displayStrips(nthreads, false));
    if (strips) pipeline.addInput(strips->input(true));
    const bool written = pipeline.run([&](StripContext& strip) {
        if (!encodeStrip(strip, in, out, spec, recipe, hdr, strips != nullptr, nthreads))
            return false;
        const OIIO::ImageBuf& rows = *strip.output;
        if (file.writeRows(strip.rows.ybegin, strip.rows.yend,
                           rows.pixeladdr(strip.rows.xbegin, strip.rows.ybegin)))
            return true;
        strip.error = file.geterror();
        return false;
    });
    if (!written) return tool.fail(pipeline.error()), false;
    if (strips) strips->report();
    return file.commit() || (tool.fail(file.geterror()), false);
}

// Whether `out` goes through writePng: a PNG whose pixels it gives as OpenImageIO would,
// without a --compression for OpenImageIO, unless --png-writer oiio asks for the reference.
bool dhdrPng(const Tool& tool, const FrameJob& job, const std::string& out,
             const OIIO::ImageSpec& spec) {
    return job.pngWriter == "dhdr" && lowerExtension(out) == ".png" &&
           tool.commandLine().compression().empty() && PngFileWriter::handles(spec);
}

} // namespace

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
    FrameRecipe recipe;
    recipe.toneMap = job.params;
    recipe.display = &job.display;
    ToneMapParams& params = recipe.toneMap;
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
    // In place, once for the whole frame (reinhard-local's blur reaches across it): the frame
    // is not needed in scene-linear after this.
    if (!streaming && !toneMap(hdr, hdr, params, {}, nthreads)) {
        tool.fail(in + ": " + hdr.geterror());
        return false;
    }
    // Every format gets the same display-referred values; only their quantization differs.
    const bool exr = lowerExtension(out) == ".exr";
    const OIIO::TypeDesc type = exr              ? OIIO::TypeDesc::HALF
                                : job.bits == 16 ? OIIO::TypeDesc::UINT16
                                                 : OIIO::TypeDesc::UINT8;
    recipe.type = exr ? OIIO::TypeDesc::FLOAT : type;
    recipe.dither = job.dither;
    const OIIO::ImageSpec spec =
        outputSpec(job, in, streaming ? strips.spec() : hdr.spec(), recipe, type, used);
    SceneLinearStrips* rows = streaming ? &strips : nullptr;
    if (dhdrPng(tool, job, out, spec))
        return writePng(tool, in, out, spec, recipe, hdr, rows, nthreads);
    return writeDisplay(tool, in, out, spec, recipe, hdr, rows, nthreads);
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
