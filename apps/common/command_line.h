// Command-line parsing with the conventions every dhdr tool shares (docs/tools.md):
// `dhdr-<stage> INPUT... -o OUTPUT [options]`, --help, --version, -v, -q, --threads N.
#pragma once

#include <dhdr/common/param_table.h>
#include <dhdr/io/pixel_limit.h>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace dhdr::app {

// --threads when not given: one worker per core.
inline constexpr int kDefaultThreads = 0;

inline constexpr int kExitSuccess = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// A file that a command line names, and the option that names it ("-o", "--probes"; empty
// for a positional input).
struct NamedFile {
    std::string option, path;
};

// What the value of an option names: a file the tool reads, or one it writes. Tool::start and
// runFrames refuse an output that is one of the inputs or another output.
enum class FileRole { Input, Output };

class CommandLine {
public:
    CommandLine(std::string tool, std::string synopsis, std::string description);

    // A switch without a value.
    void flag(const std::string& name, bool& target, const std::string& help);
    // A switch that calls `given` when it is given.
    void flag(const std::string& name, std::function<void()> given, const std::string& help);
    // An option with a value; `parse` converts it and returns false with a message when it
    // cannot. `metavar` names the value in --help.
    void option(const std::string& name, const std::string& metavar, const std::string& help,
                std::function<bool(const std::string&, std::string&)> parse);
    void option(const std::string& name, std::string& target, const std::string& metavar,
                const std::string& help);
    // Numbers: NaN and ±Inf are never accepted, and a value outside [lo, hi] (open at an end
    // where `openLo`/`openHi`) is a usage error. The range is shown in --help.
    using Range = ParamRange;
    void option(const std::string& name, double& target, const std::string& metavar,
                const std::string& help, Range range);
    // A number stored as a float: checked as the float it becomes, so that 1e39 (+Inf as a
    // float) or 1e-50 (0) cannot pass a range that the double would; `range` must lie within
    // a float's (±3.4e38).
    void option(const std::string& name, float& target, const std::string& metavar,
                const std::string& help, Range range);
    void option(const std::string& name, int& target, const std::string& metavar,
                const std::string& help, int lo, int hi);
    // A switch with an optional number after it (`--ground-plane` or `--ground-plane 0.2`,
    // `--ground-plane=0.2`): `given` is set, and `value` when a number follows.
    // The number must lie in `range` as the float it becomes (the value is used as a float).
    void flagWithNumber(const std::string& name, bool& given, std::optional<double>& value,
                        const std::string& metavar, const std::string& help, Range range);
    // Marks the option `name` (declared before) as naming a file read or written. `path`
    // turns a value into the file it names, or "" for a keyword that names none (--plate
    // env); by default the value itself.
    void namesFile(const std::string& name, FileRole role,
                   std::function<std::string(const std::string&)> path = {});
    // Text printed after the options in --help (examples, notes).
    void epilog(const std::string& text) { m_epilog = text; }
    // What --help says --frames does, for a tool whose frames are not a pattern in its input.
    void framesHelp(const std::string& text) { m_framesHelp = text; }

    // Parses argv. Returns -1 to go on, or the exit status to leave with (0 after --help or
    // --version, 2 after a usage error, which is printed).
    int parse(int argc, char** argv);

    const std::vector<std::string>& inputs() const { return m_inputs; }
    const std::string& output() const { return m_output; }
    int threads() const { return m_threads; }
    // --max-pixels (0: no limit); also in force through maxPixels() once parsed.
    long long maxPixelsGiven() const { return m_maxPixels; }
    // --compression: the output's compression as OpenImageIO names it; empty: its default.
    const std::string& compression() const { return m_compression; }
    // --frames A-B for frame patterns; empty when not given.
    const std::string& frames() const { return m_frames; }
    // 0 quiet, 1 normal, 2 verbose.
    int verbosity() const { return m_verbosity; }
    // Whether option `name` (one declared with option() or flag()) was on the command line.
    bool given(const std::string& name) const;
    // The files the options marked by namesFile named, in the order given (-o is output()).
    const std::vector<NamedFile>& inputFiles() const { return m_inputFiles; }
    const std::vector<NamedFile>& outputFiles() const { return m_outputFiles; }

private:
    struct Option {
        std::string name, metavar, help;
        std::function<bool(const std::string&, std::string&)> parse; // null for flags
        bool* flag = nullptr;
        std::function<void()> given;             // a callback flag's
        std::optional<double>* number = nullptr; // flagWithNumber's value
        Range numberRange{0.0, 0.0};             // and its range
        std::optional<FileRole> role;            // namesFile
        std::function<std::string(const std::string&)> filePath;
    };
    void printHelp() const;
    int usageError(const std::string& message) const;

    std::string m_tool, m_synopsis, m_description, m_epilog;
    std::string m_framesHelp = "frames of a pattern (in.####.exr, in.%04d.exr) in the input and "
                               "output (default: every frame whose input exists)";
    std::vector<Option> m_options;
    std::vector<std::string> m_inputs;
    std::vector<std::string> m_given; // the declared options parsed
    std::vector<NamedFile> m_inputFiles, m_outputFiles;
    std::string m_output;
    std::string m_compression;
    std::string m_frames;
    int m_threads = kDefaultThreads;
    long long m_maxPixels = kDefaultMaxPixels;
    int m_verbosity = 1;
};

// The largest --threads: OpenEXR's pool refuses far more threads than a machine has cores.
inline constexpr int kMaxThreads = 512;

// "WxH" → width, height.
bool parseSize(const std::string& text, int& width, int& height);
// "a,b,c,..." → finite numbers; false unless exactly `count` (count 0: any).
bool parseNumbers(const std::string& text, std::vector<double>& values, size_t count = 0);
// Empty when `value`, stored as a float, stays finite; else "V is more than a float holds
// (3.4e38 in magnitude)" (V as given in `text`). (A value that a float rounds to 0 is left to
// the range of the option that takes it: CommandLine's float options.)
std::string floatProblem(double value, const std::string& text);
// parseNumbers for values used as floats: false with `error` (floatProblem) when one is not.
bool parseFloatNumbers(const std::string& text, std::vector<double>& values, size_t count,
                       std::string& error);

} // namespace dhdr::app
