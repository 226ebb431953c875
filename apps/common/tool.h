// What every dhdr tool does the same way: messages, reading inputs, writing outputs
// atomically, and progress on a terminal.
#pragma once

#include "command_line.h"

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <atomic>
#include <dhdr/io/errors.h>
#include <dhdr/io/image_output.h>
#include <dhdr/io/sanitize.h>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace dhdr {
class ColourStripReader;
}

namespace dhdr::app {

class Tool {
public:
    Tool(std::string name, const CommandLine& cl) : m_name(std::move(name)), m_cl(cl) {}

    const std::string& name() const { return m_name; }
    // --threads, or after start() the fewer that could start (ulimit -v caps their stacks).
    int threads() const { return m_threads >= 0 ? m_threads : m_cl.threads(); }
    bool verbose() const { return m_cl.verbosity() >= 2; }
    bool quiet() const { return m_cl.verbosity() == 0; }

    // "dhdr-x: error: <message>" on stderr; returns kExitFailure for `return tool.fail(...)`.
    int fail(const std::string& message) const;
    void warn(const std::string& message) const;
    // Printed with -v only.
    void info(const std::string& message) const;
    // What a library call returned to say: `warnings` (warn), then `notes` (info).
    void say(const std::vector<std::string>& warnings, const std::vector<std::string>& notes) const;

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
    // The first part of `path` whose spec `wanted` accepts (part 0 when none does), its size
    // checked against the pixel limits: its index and spec, or -1 after the tool's error.
    int findPart(const std::string& path, const std::function<bool(const OIIO::ImageSpec&)>& wanted,
                 OIIO::ImageSpec& spec) const;
    // Warns that `path` has no surface in view (its alpha is 0 everywhere: hasSurface).
    void warnNoSurface(const std::string& path) const;
    // One warning line with the counts of non-finite (and with `zeroNegative` negative)
    // values dhdr::replaceNonFinite replaced in `path`; nothing when there are none.
    void reportNonFinite(const std::string& path, const NonFiniteCount& counts,
                         bool zeroNegative) const;

    // Writes `path` through `write`, which fills the temporary it is given (keeping the
    // extension) and returns false with a reason; renamed into place only when complete.
    bool writeAtomically(const std::string& path,
                         const std::function<bool(const std::string&, std::string&)>& write) const;
    // Writes a small text file (a lights file) the same way.
    bool writeText(const std::string& text, const std::string& path) const;

    const CommandLine& commandLine() const { return m_cl; }

private:
    std::string m_name;
    const CommandLine& m_cl;
    mutable int m_threads = -1;
};

// Whether `image` shows a surface over `roi` (default: all of it): some pixel's alpha
// (channel 3, as the tools read colour) is not 0, or it has no alpha at all.
bool hasSurface(const OIIO::ImageBuf& image, OIIO::ROI roi = {});

// An ImageFileOutput (dhdr/io/image_output.h) that prints its errors as the tool's, and its
// warnings once committed; the header names the tool and takes --compression.
class AtomicOutput {
public:
    AtomicOutput(const Tool& tool, std::string path);

    bool open(const OIIO::ImageSpec& spec, const std::vector<OIIO::TypeDesc>& formats) {
        return report(m_file.open(spec, formats));
    }
    bool openDeep(const OIIO::ImageSpec& spec) { return report(m_file.openDeep(spec)); }
    bool writeRows(int ybegin, int yend, const float* pixels) {
        return report(m_file.writeRows(ybegin, yend, pixels));
    }
    bool writeDeepRows(int ybegin, int yend, const OIIO::DeepData& samples) {
        return report(m_file.writeDeepRows(ybegin, yend, samples));
    }
    bool commit();
    // The file, for a StripPipeline (whose errors the caller prints).
    ImageFileOutput& file() { return m_file; }

private:
    bool report(bool ok) const;

    const Tool& m_tool;
    ImageFileOutput m_file;
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
    // update() with `done` of `total` items (pixels) after the percentage: printed when the
    // percentage changes and otherwise at most every half second, so that the line moves
    // when a percent is minutes of work.
    void update(float fraction, long long done, long long total, const char* items);
    // update() for a StripPipeline, its fraction mapped onto [from, to].
    std::function<void(float)> over(float from = 0.0f, float to = 1.0f) {
        return [this, from, to](float f) { update(from + (to - from) * f); };
    }

private:
    std::string m_label;
    bool m_enabled = false;
    std::atomic<int> m_percent{-1};
    std::atomic<long long> m_printedAt{0}; // steady clock, ns
    std::mutex m_mutex;
};

} // namespace dhdr::app
