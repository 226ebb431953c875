#include "frames.h"

#include "tool.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <dhdr/io/exr_header.h>
#include <filesystem>
#include <regex>

namespace fs = std::filesystem;

namespace dhdr::app {

FramePattern::FramePattern(std::string path) : m_text(std::move(path)) {
    // `####`: the last run of hashes in the file name.
    const size_t name =
        m_text.find_last_of('/') == std::string::npos ? 0 : m_text.find_last_of('/') + 1;
    const size_t end = m_text.find_last_of('#');
    if (end != std::string::npos && end >= name) {
        size_t begin = end;
        while (begin > name && m_text[begin - 1] == '#')
            --begin;
        m_prefix = m_text.substr(0, begin);
        m_suffix = m_text.substr(end + 1);
        m_width = int(end - begin + 1);
        return;
    }
    // `%d` or `%0Nd`.
    static const std::regex printfStyle("%(0?([0-9]*))d");
    std::smatch m;
    const std::string file = m_text.substr(name);
    if (std::regex_search(file, m, printfStyle)) {
        m_prefix = m_text.substr(0, name + size_t(m.position(0)));
        m_suffix = m_text.substr(name + size_t(m.position(0) + m.length(0)));
        // More digits than any width could need: past kMaxFrameWidth, without overflowing.
        m_width = m[2].length() > 6 ? 1000000 : m[2].length() ? std::atoi(m[2].str().c_str()) : 0;
    }
}

std::string FramePattern::path(int frame) const {
    if (!isSequence()) return m_text;
    // Sized for the width, so that no width truncates (Tool::start refuses those past
    // kMaxFrameWidth); a fixed buffer cut wide patterns to one name for every frame.
    std::string digits(size_t(std::max(m_width, 0)) + 16, '\0');
    const int n = std::snprintf(digits.data(), digits.size(), "%0*d", m_width, frame);
    digits.resize(size_t(std::max(n, 0)));
    return m_prefix + digits + m_suffix;
}

std::vector<int> FramePattern::existingFrames() const {
    std::vector<int> frames;
    if (!isSequence()) return frames;
    const fs::path prefix(m_prefix);
    const fs::path folder = prefix.has_parent_path() ? prefix.parent_path() : fs::path(".");
    const std::string stem = prefix.filename().string();
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() <= stem.size() + m_suffix.size() || name.rfind(stem, 0) != 0 ||
            name.compare(name.size() - m_suffix.size(), m_suffix.size(), m_suffix) != 0)
            continue;
        const std::string digits =
            name.substr(stem.size(), name.size() - stem.size() - m_suffix.size());
        if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
        if (m_width > 0 && int(digits.size()) != m_width) continue;
        frames.push_back(std::atoi(digits.c_str()));
    }
    std::sort(frames.begin(), frames.end());
    return frames;
}

std::string frameRangeText() {
    return "frames in [" + std::to_string(kMinFrame) + ", " + std::to_string(kMaxFrame) +
           "], at most " + std::to_string(kMaxFrameCount) + " of them";
}

bool parseFrameRange(const std::string& text, int& first, int& last) {
    auto number = [](const char* from, const char*& to, long long& value) {
        char* end = nullptr;
        errno = 0;
        value = std::strtoll(from, &end, 10);
        to = end;
        return end != from && errno != ERANGE && value >= kMinFrame && value <= kMaxFrame;
    };
    long long a = 0, b = 0;
    const char* end = nullptr;
    if (!number(text.c_str(), end, a)) return false;
    if (*end == '\0') {
        b = a;
    } else {
        if (*end != '-' || !number(end + 1, end, b) || *end != '\0') return false;
    }
    if (b < a || b - a >= kMaxFrameCount) return false;
    first = int(a);
    last = int(b);
    return true;
}

std::string sequenceStatus(size_t done, size_t total, std::chrono::steady_clock::time_point start) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double rate = seconds > 0.0 ? double(done) / seconds : 0.0;
    char text[96];
    std::snprintf(text, sizeof text, "(%zu/%zu frames, %.1f frames/s, %.0f s left)  ", done, total,
                  rate, rate > 0.0 ? double(total - done) / rate : 0.0);
    return text;
}

namespace {

int resolveFrames(const Tool& tool, const std::vector<std::string>& paths, FramePlan& plan) {
    if (const int status = tool.start(paths); status >= 0) return status;
    plan.inputs.clear();
    for (const std::string& path : paths)
        plan.inputs.emplace_back(path);
    plan.output = FramePattern(tool.commandLine().output());
    const std::vector<FramePattern>& inputs = plan.inputs;
    const FramePattern& output = plan.output;
    std::vector<int>& frames = plan.frames;
    const FramePattern* first = nullptr;
    for (const FramePattern& p : inputs)
        if (p.isSequence() && !first) first = &p;
    const std::string& range = tool.commandLine().frames();
    if (!output.isSequence()) {
        if (first || !range.empty()) {
            std::fprintf(stderr,
                         "%s: usage error: a frame pattern or --frames needs a frame "
                         "pattern in the output too (out.####.exr)\n",
                         tool.name().c_str());
            return kExitUsage;
        }
        frames = {0};
        return -1;
    }
    frames.clear();
    if (!range.empty()) {
        int a = 0, b = 0;
        if (!parseFrameRange(range, a, b)) {
            std::fprintf(stderr, "%s: usage error: --frames must be A-B, %s\n", tool.name().c_str(),
                         frameRangeText().c_str());
            return kExitUsage;
        }
        for (int f = a; f <= b; ++f)
            frames.push_back(f);
        return -1;
    }
    if (!first) {
        std::fprintf(stderr,
                     "%s: usage error: %s: a frame pattern ('#' and %%d in a file name stand for "
                     "the frame number) in the output needs --frames or a patterned input\n",
                     tool.name().c_str(), output.text().c_str());
        return kExitUsage;
    }
    frames = first->existingFrames();
    if (frames.empty()) return tool.fail(first->text() + ": no frames match the pattern");
    return -1;
}

} // namespace

int planFrames(const Tool& tool, const std::vector<std::string>& paths, FramePlan& plan) {
    if (const int status = resolveFrames(tool, paths, plan); status >= 0) return status;
    // Before any input is read: no output of any frame is an input or another output.
    return checkFrameOutputs(tool, plan, plan.frames);
}

int checkFrameOutputs(const Tool& tool, const FramePlan& plan, const std::vector<int>& frames) {
    std::vector<std::string> texts;
    for (const FramePattern& in : plan.inputs)
        texts.push_back(in.text());
    return checkFrameOutputs(tool, texts, plan.output.text(), frames);
}

int checkFrameOutputs(const Tool& tool, const std::vector<std::string>& inputs,
                      const std::string& output, const std::vector<int>& frames) {
    // Every input and output of every frame, the files options name included (a frame
    // pattern in --deep-out, a plain --probes file that one frame of -o would be).
    std::vector<NamedFile> inFiles, outFiles;
    tool.files(inputs, output, inFiles, outFiles);
    auto patterns = [](const std::vector<NamedFile>& files) {
        std::vector<FramePattern> p;
        for (const NamedFile& f : files)
            p.emplace_back(f.path);
        return p;
    };
    const std::vector<FramePattern> inPatterns = patterns(inFiles),
                                    outPatterns = patterns(outFiles);
    for (int f : frames) {
        std::vector<NamedFile> in = inFiles, out = outFiles;
        for (size_t k = 0; k < in.size(); ++k)
            in[k].path = inPatterns[k].path(f);
        for (size_t k = 0; k < out.size(); ++k)
            out[k].path = outPatterns[k].path(f);
        if (!tool.outputsAreTheirOwn(in, out)) return kExitUsage;
    }
    return -1;
}

int runFrames(
    const Tool& tool, const FramePlan& plan,
    const std::function<bool(int, const std::vector<std::string>&, const std::string&)>& frame) {
    const std::vector<int>& frames = plan.frames;
    const std::vector<FramePattern>& inputs = plan.inputs;
    const FramePattern& output = plan.output;
    Progress progress(tool, tool.name());
    size_t failures = 0, done = 0;
    for (int f : frames) {
        std::vector<std::string> paths;
        for (const FramePattern& in : inputs)
            paths.push_back(in.path(f));
        // OpenEXR 3.1 allocates what a header claims and OpenImageIO 2.4 aborts on an unknown
        // pixel type: every input EXR's headers are looked at before either reads it.
        bool fits = true;
        for (const std::string& p : paths)
            if (std::string error; fits && !detail::exrHeadersFit(p, error)) {
                tool.fail(p + ": " + error);
                fits = false;
            }
        if (!fits || !frame(f, paths, output.path(f))) ++failures;
        if (output.isSequence()) progress.update(float(++done) / float(frames.size()));
    }
    if (failures == 0) return kExitSuccess;
    if (frames.size() > 1)
        tool.fail(std::to_string(failures) + " of " + std::to_string(frames.size()) +
                  " frames failed (see above)");
    return kExitFailure;
}

} // namespace dhdr::app
