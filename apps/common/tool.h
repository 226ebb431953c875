// What every dhdr tool does the same way: messages, reading inputs, writing outputs
// atomically, and progress on a terminal.
#pragma once

#include "command_line.h"

#include <OpenImageIO/imagebuf.h>

#include <atomic>
#include <mutex>
#include <string>
#include <vector>

namespace dhdr::app {

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

    // Applies --threads to OpenImageIO's pool and checks the output: given, not one of the
    // inputs, in a folder that exists. Returns -1 to go on, else the exit status.
    int start(const std::vector<std::string>& inputs) const;

    // Reads the whole of `path` into float pixels; false after printing the error.
    bool readImage(const std::string& path, OIIO::ImageBuf& image) const;

    // Replaces NaN and ±Inf in channels [chbegin, chend) and warns with the counts.
    void replaceNonFinite(const std::string& path, OIIO::ImageBuf& image, int chbegin,
                          int chend) const;

    // Writes `image` to a temporary file beside `path` and renames it into place, so that a
    // failed or interrupted run leaves no partial output. `formats`: one type for all
    // channels, or one per channel; empty keeps float.
    bool writeImage(const OIIO::ImageBuf& image, const std::string& path,
                    const std::vector<OIIO::TypeDesc>& formats = {}) const;

private:
    std::string m_name;
    const CommandLine& m_cl;
};

// A progress line on stderr when stderr is a terminal and the tool is not quiet.
class Progress {
public:
    Progress(const Tool& tool, std::string label);
    ~Progress();
    // Thread-safe; prints only when the whole percentage changes.
    void update(float fraction);

private:
    std::string m_label;
    bool m_enabled = false;
    std::atomic<int> m_percent{-1};
    std::mutex m_mutex;
};

} // namespace dhdr::app
