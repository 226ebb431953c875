// Frame patterns: `shot.####.exr` (one # per digit) or printf style `shot.%04d.exr`, and the
// frame ranges that go with them (`--frames 1-100`).
#pragma once

#include <chrono>
#include <dhdr/common/frame_limits.h>
#include <functional>
#include <string>
#include <vector>

namespace dhdr::app {

class FramePattern {
public:
    // A path with no pattern in it is a single file.
    explicit FramePattern(std::string path);

    bool isSequence() const { return m_width >= 0; }
    // Digits of the frame number (0: no padding); −1 when not a sequence.
    int width() const { return m_width; }
    // The path of `frame` (the path itself when it is not a sequence).
    std::string path(int frame) const;
    const std::string& text() const { return m_text; }
    // The frames whose files exist, ascending (by listing the folder).
    std::vector<int> existingFrames() const;

private:
    std::string m_text, m_prefix, m_suffix;
    int m_width = -1; // digits (0: no padding); −1: not a sequence
};

// --frames' limits (dhdr/common/frame_limits.h) as its messages state them: "frames in
// [-99999999, 999999999], at most 1000000 of them".
std::string frameRangeText();

// The widest frame pattern (#### or %0Nd): frame numbers have at most 9 digits and a sign,
// and a wider pattern is a typo. dhdr-farm has the same limit (dhdr_farm/frames.py).
inline constexpr int kMaxFrameWidth = 16;

// "A-B" or "A" → [A, B]; false when malformed, B < A, or outside the limits above.
bool parseFrameRange(const std::string& text, int& first, int& last);

class Tool;

// "(12/100 frames, 4.1 frames/s, 21 s left)" for a progress line.
std::string sequenceStatus(size_t done, size_t total, std::chrono::steady_clock::time_point start);

// What a command line asks to process: its input paths and output as patterns, and the frames.
struct FramePlan {
    std::vector<FramePattern> inputs;
    FramePattern output{std::string()};
    std::vector<int> frames;
};

// Checks the output (Tool::start), resolves the frames, and checks that no output of any
// frame is one of its inputs or another output (checkFrameOutputs). With a frame pattern in the
// output, every pattern among `inputs` expands frame by frame (plain paths stay as they are) over
// --frames, or over the frames whose first patterned input exists. Without one, there is one
// frame and no input may be a pattern. Returns −1 to go on, or the exit status after printing
// why not.
int planFrames(const Tool& tool, const std::vector<std::string>& inputs, FramePlan& plan);

// Checks, frame by frame, that no output (`output` and the files options write: --deep-out)
// is an input (`inputs` and the files options read: --probes) or another output, each frame
// pattern expanded (Tool::outputsAreTheirOwn). Returns −1 to go on, else the exit status (2)
// after printing why not.
int checkFrameOutputs(const Tool& tool, const std::vector<std::string>& inputs,
                      const std::string& output, const std::vector<int>& frames);
int checkFrameOutputs(const Tool& tool, const FramePlan& plan, const std::vector<int>& frames);

// Runs `frame(number, inputs, output)` for each frame of a plan made by planFrames (which has
// checked the outputs) in turn, with a progress line for sequences. Returns the exit status.
int runFrames(
    const Tool& tool, const FramePlan& plan,
    const std::function<bool(int, const std::vector<std::string>&, const std::string&)>& frame);

} // namespace dhdr::app
