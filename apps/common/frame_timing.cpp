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
    if ((frame || time) && (FramePattern(cl.output()).isSequence() || !cl.frames().empty())) {
        std::fprintf(stderr,
                     "%s: usage error: --frame and --time make one frame into one file: give -o "
                     "without a frame pattern (or --frames A-B with one)\n",
                     name);
        return kExitUsage;
    }
    return -1;
}

} // namespace dhdr::app
