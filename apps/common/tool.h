// What every dhdr tool does the same way: messages, reading inputs, writing outputs
// atomically, and progress on a terminal.
#pragma once

#include "command_line.h"

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <atomic>
#include <dhdr/deferred/deep_exr.h>
#include <dhdr/tonemap/sanitize.h>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace dhdr::app {

class ColourStripReader;

// "PATH: cannot read: ERROR", or "PATH: ERROR" for an image over --max-pixels
// (pixelLimitError), whose message says what is wrong by itself.
std::string cannotRead(const std::string& path, const std::string& error);

class Tool {
public:
    Tool(std::string name, const CommandLine& cl) : m_name(std::move(name)), m_cl(cl) {}

    const std::string& name() const { return m_name; }
    int threads() const { return m_cl.threads(); }
    bool verbose() const { return m_cl.verbosity() >= 2; }
    bool quiet() const { return m_cl.verbosity() == 0; }

    // "dhdr-x: error: <message>" on stderr; returns kExitFailure for `return tool.fail(...)`.
    int fail(const std::string& message) const;
    void warn(const std::string& message) const;
    // Printed with -v only.
    void info(const std::string& message) const;

    // Applies --threads to OpenImageIO's pool and checks the output: given, in a folder that
    // exists, and neither an input (`inputs` or a file an option reads: namesFile) nor
    // another output (--deep-out, --lights-out, --stats-out). Returns -1 to go on, else the
    // exit status (2 for an output that would overwrite an input).
    int start(const std::vector<std::string>& inputs) const { return start(inputs, m_cl.output()); }
    // The same for a tool whose output is not -o (dhdr-tonemap --meter-only's statistics).
    int start(const std::vector<std::string>& inputs, const std::string& out) const;

    // The inputs and outputs of the command line: `inputs` (positional, or their frame
    // patterns) and `out`, with the files its options name.
    void files(const std::vector<std::string>& inputs, const std::string& out,
               std::vector<NamedFile>& in, std::vector<NamedFile>& outs) const;
    // Whether every output is a file of its own: none the same file as an input (compared by
    // filesystem identity when both exist, else by their normalized paths) or as another
    // output. Prints why not and returns false.
    bool outputsAreTheirOwn(const std::vector<NamedFile>& inputs,
                            const std::vector<NamedFile>& outputs) const;

    // Reads the colour of `path` found by name (layers.h): layer or part `layer` (--layer),
    // or the one the conventions name. Channels 0–2 (3) of `image` are then R, G, B (A); with
    // `keepOthers` the part's other channels follow. `formats` receives the file's type of
    // each channel. -v says which layer was read when the file has several.
    bool readColour(const std::string& path, const std::string& layer, bool keepOthers,
                    OIIO::ImageBuf& image, std::vector<OIIO::TypeDesc>& formats,
                    int nthreads) const;
    // Opens the colour of `path` (as readColour finds it) for reading strip by strip.
    bool openColour(const std::string& path, const std::string& layer, bool keepOthers,
                    ColourStripReader& reader) const;
    // Warns that `path` has no surface in view (its alpha is 0 everywhere: hasSurface).
    void warnNoSurface(const std::string& path) const;
    // One warning line with the counts of non-finite (and with `zeroNegative` negative)
    // values dhdr::replaceNonFinite replaced in `path`; nothing when there are none.
    void reportNonFinite(const std::string& path, const NonFiniteCount& counts,
                         bool zeroNegative) const;

    // Writes a small text file (a lights file) as AtomicOutput writes images: temporary
    // name, then rename.
    // Writes `path` through `write`, which fills the temporary it is given (keeping the
    // extension) and returns false with a reason; renamed into place only when complete.
    bool writeAtomically(const std::string& path,
                         const std::function<bool(const std::string&, std::string&)>& write) const;
    bool writeText(const std::string& text, const std::string& path) const;

    const CommandLine& commandLine() const { return m_cl; }

private:
    std::string m_name;
    const CommandLine& m_cl;
};

// Whether `image` shows a surface over `roi` (default: all of it): some pixel's alpha
// (channel 3, as the tools read colour) is not 0, or it has no alpha at all.
bool hasSurface(const OIIO::ImageBuf& image, OIIO::ROI roi = {});

class NativeWriter;

// An output file written under a temporary name in its folder (same extension, so the
// format is the same) and renamed into place by commit(): a failed or interrupted run never
// leaves a partial file. Every temporary open in the process is removed on SIGHUP, SIGINT,
// SIGTERM and fatal signals; temporaries of the same output left by a process that is gone
// (killed with SIGKILL) are removed when it is written again. Rows can be written as they
// are produced. Output is scanline whatever the input was, and never holds NaN or Inf:
// NaN becomes 0, ±Inf and values past half's ±65504 in half channels the type's largest
// value, each counted in one warning at commit() (a G-buffer's Z keeps the +Inf of its
// background, which the contract gives it).
class AtomicOutput {
public:
    AtomicOutput(const Tool& tool, std::string path);
    ~AtomicOutput();
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;

    // Opens the temporary file for an image of `spec`; rows are then given as float pixels.
    // `formats`: one type for all channels, or one per channel; empty keeps float. Errors
    // are printed, naming the output.
    bool open(OIIO::ImageSpec spec, const std::vector<OIIO::TypeDesc>& formats);
    // Opens the temporary file for a deep scanline image of `spec` (its channelformats the
    // samples' types); rows are then given as DeepData. Written through OpenEXR itself
    // (dhdr/deferred/deep_exr.h: OpenImageIO 2.4.7 overflows on large deep frames).
    bool openDeep(OIIO::ImageSpec spec);
    bool writeDeepRows(int ybegin, int yend, const OIIO::DeepData& samples);
    // Rows [ybegin, yend), contiguous float pixels of all channels. Thread-compatible: one
    // caller at a time.
    bool writeRows(int ybegin, int yend, const float* pixels);
    // Computes one strip of rows (all channels) into `pixels`, contiguous, of the type given
    // to writeStrips; false after printing an error.
    using StripFill = std::function<bool(OIIO::ROI strip, void* pixels)>;
    // Writes the whole image in strips of `rows` rows that `fill` computes. With `overlap`,
    // the next strip is computed on another thread while this one is encoded, so that
    // single-threaded encoders (PNG, JPEG) run alongside the work that feeds them.
    bool writeStrips(OIIO::TypeDesc type, int rows, bool overlap, const StripFill& fill);
    // Closes the file and renames it into place.
    bool commit();

private:
    // Registers the temporary (removed on any exit) and opens it for `spec`.
    bool openTemporary(const OIIO::ImageSpec& spec);

    const Tool& m_tool;
    std::string m_path, m_temporary;
    std::unique_ptr<OIIO::ImageOutput> m_out;
    std::unique_ptr<DeepScanlineWriter> m_deep;
    std::unique_ptr<NativeWriter> m_native; // null: OIIO converts (8/16-bit formats)
    std::vector<std::byte> m_buffer;
    long long m_clamped = 0, m_nonFinite = 0;
    bool m_committed = false;
};

// Runs a tool's body: an exception that escapes it (out of memory, or one from a library)
// becomes "NAME: error: …" and exit status 1 rather than an abort; outputs in progress are
// removed as the stack unwinds.
int guardedMain(const char* name, const std::function<int()>& body);

// A progress line on stderr when stderr is a terminal and the tool is not quiet.
class Progress {
public:
    Progress(const Tool& tool, std::string label);
    ~Progress();
    // Thread-safe; prints only when the whole percentage changes. `detail` follows it.
    void update(float fraction, const std::string& detail = {});

private:
    std::string m_label;
    bool m_enabled = false;
    std::atomic<int> m_percent{-1};
    std::mutex m_mutex;
};

} // namespace dhdr::app
