// Frame patterns: `shot.####.exr` (one # per digit) or printf style `shot.%04d.exr`, and the
// frame ranges that go with them (`--frames 1-100`).
#pragma once

#include <string>
#include <vector>

namespace dhdr::app {

class FramePattern {
public:
    // A path with no pattern in it is a single file.
    explicit FramePattern(std::string path);

    bool isSequence() const { return m_width >= 0; }
    // The path of `frame` (the path itself when it is not a sequence).
    std::string path(int frame) const;
    const std::string& text() const { return m_text; }
    // The frames whose files exist, ascending (by listing the folder).
    std::vector<int> existingFrames() const;

private:
    std::string m_text, m_prefix, m_suffix;
    int m_width = -1; // digits (0: no padding); −1: not a sequence
};

// "A-B" or "A" → [A, B]; false when malformed or B < A.
bool parseFrameRange(const std::string& text, int& first, int& last);

} // namespace dhdr::app
