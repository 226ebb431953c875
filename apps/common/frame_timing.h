// --frame, --time, --fps and --animation: which moment of the scene's animation each frame of
// a run shows, parsed and checked in one place for the tools that pose a scene (dhdr-gbuffer,
// dhdr-probes; docs/animation.md). --frames is every tool's (command_line.h).
#pragma once

#include "command_line.h"

#include <dhdr/deferred/scene/animation.h>
#include <optional>
#include <string>

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

    // Declares the four options, with one help text for every tool that takes them.
    void declare(CommandLine& cl);

    // After parsing: takes --frame and --time when given, then their usage errors with the
    // run's output and --frames: they exclude each other, and each makes one file (no frame
    // pattern in -o, no --frames). Returns -1 to go on, else the exit status (2) after
    // printing why not.
    int check(const Tool& tool);
};

} // namespace dhdr::app
