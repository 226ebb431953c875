#include "frame_probes.h"

#include "../common/frames.h"
#include "../common/tool.h"

#include <chrono>
#include <cstdio>
#include <dhdr/deferred/gbuffer/gbuffer_time.h>
#include <filesystem>

namespace dhdr::app {

namespace {

// "0.5 s (frame 12 at 24 fps, animation 0)": a moment as a message names it, with the frame
// a TD knows it by when the frame rate is recorded.
std::string describe(const gbuffer::Moment& m) {
    char text[128];
    std::snprintf(text, sizeof text, "%.9g s (", m.time);
    std::string out = text;
    if (m.fps > 0.0) {
        std::snprintf(text, sizeof text, "frame %.9g at %.9g fps, ", m.time * m.fps, m.fps);
        out += text;
    }
    return out + "animation " +
           (m.animations ? gbuffer::formatAnimations(*m.animations) : std::string("0")) + ")";
}

// The animations that played: unrecorded means the file's first (dhdr-gbuffer's default).
std::vector<int> playing(const gbuffer::Moment& m) {
    return m.animations ? *m.animations : std::vector<int>{0};
}

} // namespace

FrameProbes::FrameProbes(std::string option, size_t frames)
    : m_option(std::move(option)), m_perFrame(FramePattern(m_option).isSequence()),
      m_oneFrame(frames == 1) {}

bool FrameProbes::read(const Tool& tool, const std::string& path, int frame, DiffuseModel diffuse) {
    if (path == m_path) return true;
    m_path.clear();
    if (m_perFrame && !std::filesystem::exists(path)) {
        tool.fail(path + ": no such file (the probes of frame " + std::to_string(frame) +
                  ", --probes " + m_option + "; dhdr-probes --frames bakes them)");
        return false;
    }
    const auto t = std::chrono::steady_clock::now();
    std::string error;
    if (!readProbes(path, m_volume, error)) {
        tool.fail(path + ": " + error);
        return false;
    }
    m_path = path;
    if (m_volume.diffuse != diffuse && !m_warnedDiffuse) {
        const char* baked = m_volume.diffuse == DiffuseModel::Burley ? "burley" : "lambert";
        tool.warn(path + ": baked with --diffuse " + baked + ", shaded here with " +
                  (diffuse == DiffuseModel::Burley ? "burley" : "lambert") +
                  ": the indirect light will not match the direct (give the same --diffuse "
                  "to both tools)");
        m_warnedDiffuse = true;
    }
    tool.info(path + ": " + std::to_string(m_volume.probeCount()) + " probes read in " +
              std::to_string(int(
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t)
                      .count())) +
              " ms");
    return true;
}

bool FrameProbes::checkMoment(const Tool& tool, const std::string& gbuffer,
                              const OIIO::ImageSpec& spec) {
    const std::optional<gbuffer::Moment>& baked = m_volume.moment;
    // A still scene's bake (or one from before probes recorded their moment): a set that holds
    // at any time.
    if (!baked) return true;
    std::optional<gbuffer::Moment> shown;
    std::string error;
    if (!gbuffer::readMoment(spec, shown, error)) {
        tool.fail(gbuffer + ": " + error);
        return false;
    }
    if (!m_perFrame && !m_oneFrame) {
        if (!m_saidSet)
            tool.info(m_path + ": baked at " + describe(*baked) +
                      "; one probe file for every frame (a static set)");
        m_saidSet = true;
        return true;
    }
    if (!shown) {
        tool.warn(m_path + ": baked at " + describe(*baked) + ", but " + gbuffer +
                  " records no animation time: the indirect light may not match the pixels");
    } else if (shown->time != baked->time || playing(*shown) != playing(*baked)) {
        tool.warn(m_path + ": baked at " + describe(*baked) + ", but " + gbuffer + " shows " +
                  describe(*shown) + ": its indirect light is the other moment's");
    }
    return true;
}

} // namespace dhdr::app
