// One frame through dhdr-tonemap: read, meter, tone-map, encode. A frame is held whole in
// memory when its float pixels fit FrameJob::wholeFrameBytes, and streamed strip by strip
// otherwise (read once per metering pass and once to map), so any size maps in bounded
// memory. Both give the same pixels (tested).
#pragma once

#include "../common/tool.h"

#include <cstddef>
#include <dhdr/tonemap/display_transform.h>
#include <dhdr/tonemap/tone_map.h>
#include <string>

namespace dhdr::app {

// Everything the command line says about mapping one frame.
struct FrameJob {
    ToneMapParams params;
    DisplayTransform display;
    std::string white, weights, metering, percentiles, layer;
    int bits = 8;
    bool dither = true;
    // "dhdr": PNG through dhdr's parallel writer (png_writer.h); "oiio": through OpenImageIO,
    // the reference it is tested against (--png-writer).
    std::string pngWriter = "dhdr";
    // Frames whose float pixels need more bytes are streamed (--memory); reinhard-local,
    // whose blur reaches across the frame, always holds it whole.
    size_t wholeFrameBytes = size_t(512) << 20;
};

std::string lowerExtension(const std::string& path);

// Everything that decides a frame's metered luminance, so that statistics metered one way
// are not combined with, or applied to, frames metered another.
std::string meteringDescription(const FrameJob& job);

// Meters `in` as mapFrame does (no warnings: mapFrame gives them).
bool meterFrame(const Tool& tool, const FrameJob& job, const std::string& in, LuminanceStats& stats,
                int nthreads);

// Meters `in` (or uses `given`; or meters it and maps it with the log-average `adapted`),
// tone-maps it and writes `out`; `used` receives the metering.
bool mapFrame(const Tool& tool, const FrameJob& job, const std::string& in, const std::string& out,
              const LuminanceStats* given, const double* adapted, LuminanceStats& used,
              int nthreads);

} // namespace dhdr::app
