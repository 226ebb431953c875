// dhdr-light's --probes across the G-buffers of a run: one probe file for every frame (a set
// baked once), or with a frame pattern each G-buffer's own frame's file, read when its frame
// comes; a probe file baked at another moment than its G-buffer shows is a warning
// (docs/animation.md, "Lighting a shot").
#pragma once

#include <OpenImageIO/imageio.h>
#include <dhdr/deferred/gi/probes.h>
#include <string>

namespace dhdr::app {

class Tool;

class FrameProbes {
public:
    // `option`: --probes' value, a file or a frame pattern; `frames`: how many frames the run
    // lights (a single probe file for one G-buffer is that frame's, and checked as such).
    FrameProbes(std::string option, size_t frames);

    bool given() const { return !m_option.empty(); }
    // With a frame pattern: each frame reads its own file.
    bool perFrame() const { return m_perFrame; }

    // Reads `path` (the option's file, or its pattern at this frame) unless it is the file read
    // last; warns once when its diffuse model is not `diffuse`. False after the tool's error
    // naming the file (a frame's file that does not exist included).
    bool read(const Tool& tool, const std::string& path, int frame, DiffuseModel diffuse);

    // Compares the moment the probes were baked at with the one the G-buffer `gbuffer` (header
    // `spec`) records: a probe file meant for this frame (a pattern's, or the one file of a
    // one-frame run) at another moment is a warning naming both; one file over a sequence is
    // a set for every frame, said once under -v. False after the tool's error when the
    // G-buffer's record is malformed.
    bool checkMoment(const Tool& tool, const std::string& gbuffer, const OIIO::ImageSpec& spec);

    const ProbeVolume& volume() const { return m_volume; }

private:
    std::string m_option, m_path; // the option's value; the file read last
    bool m_perFrame = false, m_oneFrame = false;
    ProbeVolume m_volume;
    bool m_warnedDiffuse = false, m_saidSet = false;
};

} // namespace dhdr::app
