#include "frame_timing.h"

#include "frames.h"
#include "param_options.h"
#include "tool.h"

#include <cstdio>

namespace dhdr::app {

void FrameTiming::declare(CommandLine& cl) {
    addParamOptions(cl, moment, kMomentIntTable);
    addParamOptions(cl, moment, kMomentFloatTable);
    cl.option("--animation", animation, "NAME|INDEX|all",
              "the animation that plays (default: the file's first, as glTF viewers play; all: "
              "every one at once)");
}

int FrameTiming::check(const Tool& tool) {
    const CommandLine& cl = tool.commandLine();
    if (cl.given("--frame")) frame = moment.frame;
    if (cl.given("--time")) time = moment.time;
    given = frame || time;
    const char* name = tool.name().c_str();
    if (frame && time) {
        std::fprintf(stderr, "%s: usage error: --frame and --time exclude each other\n", name);
        return kExitUsage;
    }
    // The times are computed in double, but --fps is checked as the float it would be, as
    // every tool's numbers are: 1e-50 is 0, outside (0, 1e6].
    if (!(float(moment.fps) > 0.0f)) {
        std::fprintf(stderr, "%s: usage error: --fps: %g is outside %s as a float (0)\n", name,
                     moment.fps, kMomentFloatTable[0].range.text().c_str());
        return kExitUsage;
    }
    if ((frame || time) && (FramePattern(cl.output()).isSequence() || !cl.frames().empty())) {
        std::fprintf(stderr,
                     "%s: usage error: --frame and --time make one frame into one file: give -o "
                     "without a frame pattern (or --frames A-B with one)\n",
                     name);
        return kExitUsage;
    }
    return -1;
}

int FrameTiming::checkTimes(const Tool& tool, const std::vector<int>& frames) const {
    const ParamRange& range = kMomentFloatTable[1].range;
    for (const int f : {frames.front(), frames.back()})
        for (const double t : {timeBefore(f), timeOf(f), timeAfter(f)})
            if (!range.contains(t)) {
                const std::string which =
                    time ? "--time" : "frame " + std::to_string(frame ? *frame : f);
                std::fprintf(stderr,
                             "%s: usage error: --fps %g: %s (or the frame either side of it, for "
                             "the motion layer) is at %g s, outside the times %s\n",
                             tool.name().c_str(), moment.fps, which.c_str(), t,
                             range.text().c_str());
                return kExitUsage;
            }
    return -1;
}

} // namespace dhdr::app
