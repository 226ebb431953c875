// --frame, --time, --fps and --animation: which moment of the scene's animation each frame of
// a run shows, parsed and checked in one place for the tools that pose a scene (dhdr-gbuffer,
// dhdr-probes; docs/animation.md). --frames is every tool's (command_line.h).
#pragma once

#include "command_line.h"

#include <dhdr/deferred/scene/animation.h>
#include <optional>
#include <string>
#include <vector>

namespace dhdr::app {

class Tool;

struct FrameTiming {
    MomentChoice moment;        // --fps, and --frame and --time when given (animation.h's tables)
    std::optional<int> frame;   // --frame N: the frame shown (the output is one file)
    std::optional<double> time; // --time S: the time shown, seconds
    bool given = false;         // --frame or --time on the command line
    // --animation NAME|INDEX|all: what plays; empty: the file's first, as glTF viewers play.
    std::string animation;

    // Frame N shows time N / fps (frame 0 is time 0, as in Blender's glTF import and export).
    double timeOf(int planned) const {
        if (time) return *time;
        return double(frame ? *frame : planned) / moment.fps;
    }
    // The times of the frames either side, for the motion layer: (N ± 1) / fps, computed as
    // frames (not t ± 1 / fps, which lands a hair off a key on a frame); t ± 1 / fps for --time.
    double timeBefore(int planned) const { return neighbour(planned, -1.0); }
    double timeAfter(int planned) const { return neighbour(planned, 1.0); }

    // Declares the four options, with one help text for every tool that takes them.
    void declare(CommandLine& cl);

    // After parsing: takes --frame and --time when given, then their usage errors with the
    // run's output and --frames: they exclude each other, and each makes one file (no frame
    // pattern in -o, no --frames). Returns -1 to go on, else the exit status (2) after
    // printing why not.
    int check(const Tool& tool);

    // After planning: every time the run poses the scene at (each frame's and the frames' either
    // side) lies in --time's range, so that a tiny --fps (1e-45) is refused rather than posing
    // at 1e45 s. Returns -1 to go on, else the exit status (2) after printing why not.
    int checkTimes(const Tool& tool, const std::vector<int>& frames) const;

private:
    double neighbour(int planned, double step) const {
        if (time) return *time + step / moment.fps;
        return (double(frame ? *frame : planned) + step) / moment.fps;
    }
};

} // namespace dhdr::app
