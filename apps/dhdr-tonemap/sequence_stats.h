// The statistics file of a sequence (--stats-out, --scan, --adapt-from): each frame's
// metered log-average luminance and the one it is mapped with, so that metering, the
// adaptation scan and mapping can run as separate processes (docs/farm.md).
#pragma once

#include <dhdr/tonemap/adaptation.h>
#include <string>
#include <vector>

namespace dhdr::app {

struct FrameLuminance {
    int frame = 0;
    std::string file;
    double logAverage = 0.0; // the frame's own metering
    double adapted = 0.0;    // what it is mapped with (= logAverage without adaptation)
};

struct SequenceStats {
    double fps = 24.0;
    // Whether `adapted` holds the adaptation scan's values.
    bool adapt = false;
    // How the frames were metered (meteringDescription): files metered differently are not
    // combined.
    std::string metering;
    std::vector<FrameLuminance> frames;
};

// Numbers are written with 17 significant digits, so they read back as the same doubles and
// a mapping run from the file gives the same pixels as one run over the whole sequence.
std::string toJson(const SequenceStats& stats);
bool readSequenceStats(const std::string& path, SequenceStats& stats, std::string& error);

class Tool;
// --scan: the metering of every chunk of a sequence (--meter-only files), combined in frame
// order, through the adaptation scan, to one statistics file that --adapt-from maps with.
// Returns the exit status.
int scanStatistics(const Tool& tool, const std::vector<std::string>& files,
                   const AdaptationParams& adaptation, const std::string& out);

} // namespace dhdr::app
