// dhdr-gbuffer's --frame, --fps and --time: which time of the scene's animation each frame
// shows (docs/animation.md).
#pragma once

#include "../common/command_line.h"
#include "../common/frames.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>

namespace dhdr::app {

struct FrameTiming {
    double fps = 24.0;
    std::optional<int> frame;   // --frame N: the frame shown (the output is one file)
    std::optional<double> time; // --time S: the time shown, seconds
    bool given = false;         // any of the three on the command line

    // Frame N shows time N / fps (frame 0 is time 0, as in Blender's glTF import and export).
    double timeOf(int planned) const {
        if (time) return *time;
        return double(frame ? *frame : planned) / fps;
    }

    void declare(CommandLine& cl) {
        cl.option("--frame", "N",
                  "render frame N of the scene's animation (time N / fps) into the one output",
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
                  "render the scene's animation at this time, in seconds, into the one output",
                  [this](const std::string& v, std::string& error) {
                      char* end = nullptr;
                      const double t = std::strtod(v.c_str(), &end);
                      if (end == v.c_str() || *end != '\0' || !std::isfinite(t) ||
                          std::abs(t) > 1e9) {
                          error = "'" + v + "' is not a time in seconds in [-1e9, 1e9]";
                          return false;
                      }
                      time = t;
                      given = true;
                      return true;
                  });
        cl.option("--fps", fps, "F",
                  "frames a second: frame N shows the animation at time N / F (default 24)",
                  {0.0, 1e6, true, false});
    }
};

} // namespace dhdr::app
