// A frame streamed a strip of rows at a time: read ahead, sanitize, process, write, progress,
// commit. Every dhdr tool runs its frames through this one loop, and a host program can run
// its own stages through it, so that memory stays at a few strips whatever the frame's size
// and each pixel's result is the one the whole frame would give.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/io/sanitize.h>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace dhdr {

class ImageFileOutput;

struct StripPipelineParams {
    int rows = 64; // rows a strip, [1, ∞)
    int halo = 0;  // rows read above and below each strip (a filter's reach), [0, ∞)
    // The rows a strip shares with the previous one (2 × halo) are copied from the previous
    // strip's inputs instead of being read again, for the inputs that can (StripInput::
    // readReusing), while that strip is processed: the process must leave its inputs as they
    // were read. Only when halo ≤ rows.
    bool shareHalo = false;
    // The next strip is read on another thread while this one is processed.
    bool readAhead = true;
    // This strip is written on another thread while the next one is processed, so that
    // single-threaded encoders (PNG, JPEG) run alongside the work that feeds them.
    bool writeBehind = false;
    // Threads for the sanitizing (0: all cores); the stages choose their own.
    int nthreads = 0;
    // Called with the fraction of the frame done (0–1] after each strip is written; from the
    // calling thread.
    std::function<void(float)> progress;
};

// The stages of one strip. Each gets the strip's own rows (the frame's full width) and the
// slot (0 or 1, alternating from strip to strip) naming the buffers it works on: while strip
// k is processed in slot k % 2, strip k + 1 may be read into the other slot and strip k − 1
// written from it. Each returns false with `error` to stop the frame.
struct StripStages {
    using Stage = std::function<bool(OIIO::ROI rows, int slot, std::string& error)>;
    Stage read;    // optional; one strip ahead with StripPipelineParams::readAhead
    Stage process; // required
    Stage write;   // optional; one strip behind with StripPipelineParams::writeBehind
};

// Runs the stages over the rows of `frame` in strips of params.rows, in order: reads are
// sequential, and so are writes. False with `error` from the first stage that failed (the
// stages in flight are finished first).
bool runStrips(OIIO::ROI frame, const StripPipelineParams& params, const StripStages& stages,
               std::string& error);

// What a strip pipeline reads: rows of one image (a StripReader, a ColourStripReader, or
// anything that reads rows) and the channels whose non-finite values it replaces.
struct StripInput {
    // Rows [ybegin, yend), clamped to the image, as float pixels into `strip` (its memory
    // reused); false with `error`.
    std::function<bool(int ybegin, int yend, OIIO::ImageBuf& strip, std::string& error)> read;
    // The file, for messages ("PATH: cannot read: …").
    std::string name;
    // Channel ranges [first, second) where NaN and ±Inf are replaced (sanitize.h) before
    // processing; a G-buffer's Z, +Inf on the background by contract, is left out of them.
    std::vector<std::pair<int, int>> sanitize;
    // Optional (StripPipelineParams::shareHalo): as `read`, the rows that `previous` (what the
    // read gave for the strip before) holds from ybegin on copied from it; `copiedEnd` the end
    // of the rows copied (the strip's first row when none were).
    std::function<bool(int ybegin, int yend, const OIIO::ImageBuf& previous, OIIO::ImageBuf& strip,
                       int& copiedEnd, std::string& error)>
        readReusing = nullptr;
};

// One strip as the process function sees it.
struct StripContext {
    OIIO::ROI rows;                      // the strip's own rows
    std::vector<OIIO::ImageBuf*> inputs; // each input, rows ± halo (clamped), sanitized
    OIIO::ImageBuf* output = nullptr;    // to hold at least `rows`, in any pixel type
    std::string error;                   // why, when the process returns false
};

// The flat form every tool uses: inputs read (ahead) and sanitized, a process function, the
// result written to an ImageFileOutput.
class StripPipeline {
public:
    StripPipeline(OIIO::ROI frame, StripPipelineParams params)
        : m_frame(frame), m_params(std::move(params)) {}

    void addInput(StripInput input) { m_inputs.push_back(std::move(input)); }
    // Where the strips go: an output opened already, or one `open` opens from the first
    // processed strip (whose spec may decide the channels). Without, the pipeline only reads
    // and processes (a metering pass).
    void setOutput(ImageFileOutput& output,
                   std::function<bool(const OIIO::ImageBuf& first, std::string& error)> open = {});

    // Runs the frame; false with error(). The output is not committed.
    bool run(const std::function<bool(StripContext&)>& process);

    const std::string& error() const { return m_error; }
    // Non-finite values replaced in each input (in addInput order), counted on each strip's
    // own rows once: the halo is cleaned for the filter but not counted again.
    const std::vector<NonFiniteCount>& replaced() const { return m_replaced; }
    // Milliseconds spent in each stage, summed over the strips (read ahead overlaps the
    // others).
    double readMs() const { return m_readMs; }
    double processMs() const { return m_processMs; }
    double writeMs() const { return m_writeMs; }

private:
    OIIO::ROI m_frame;
    StripPipelineParams m_params;
    std::vector<StripInput> m_inputs;
    ImageFileOutput* m_output = nullptr;
    std::function<bool(const OIIO::ImageBuf&, std::string&)> m_open;
    std::vector<NonFiniteCount> m_replaced;
    std::string m_error;
    double m_readMs = 0.0, m_processMs = 0.0, m_writeMs = 0.0;
};

} // namespace dhdr
