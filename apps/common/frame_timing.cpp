#include "frame_timing.h"

#include "frames.h"
#include "tool.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace dhdr::app {

void FrameTiming::declare(CommandLine& cl) {
    cl.option("--frame", "N",
              "frame N of the scene's animation (time N / fps), into the one output (-o "
              "without a frame pattern)",
              [this](const std::string& v, std::string& error) {
                  char* end = nullptr;
                  errno = 0;
                  const long long n = std::strtoll(v.c_str(), &end, 10);
                  if (end == v.c_str() || *end != '\0' || errno == ERANGE || n < kMinFrame ||
                      n > kMaxFrame) {
                      error = "'" + v + "' is not a frame number in [-99999999, 999999999]";
                      return false;
                  }
                  frame = int(n);
                  given = true;
                  return true;
              });
    cl.option("--time", "SECONDS",
              "the scene's animation at this time, in seconds, into the one output",
              [this](const std::string& v, std::string& error) {
                  char* end = nullptr;
                  const double t = std::strtod(v.c_str(), &end);
                  if (end == v.c_str() || *end != '\0' || !std::isfinite(t) || std::abs(t) > 1e9) {
                      error = "'" + v + "' is not a time in seconds in [-1e9, 1e9]";
                      return false;
                  }
                  time = t;
                  given = true;
                  return true;
              });
    cl.option("--fps", fps, "F", "frames a second: frame N shows the animation at time N / F",
              {0.0, 1e6, true, false});
    cl.option("--animation", animation, "NAME|INDEX|all",
              "the animation that plays (default: the file's first, as glTF viewers play; all: "
              "every one at once)");
}

int FrameTiming::check(const Tool& tool) const {
    const char* name = tool.name().c_str();
    if (frame && time) {
        std::fprintf(stderr, "%s: usage error: --frame and --time exclude each other\n", name);
        return kExitUsage;
    }
    const CommandLine& cl = tool.commandLine();
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
