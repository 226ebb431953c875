#include "tool.h"

#include <dhdr/tonemap/sanitize.h>

#include <OpenImageIO/imageio.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <unistd.h>

namespace fs = std::filesystem;

namespace dhdr::app {

namespace {

// The temporary output being written, removed if the process is interrupted.
char g_temporary[4096] = {0};

void removeTemporaryAndExit(int signal) {
    if (g_temporary[0]) unlink(g_temporary);
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

// OIIO's messages end in newlines and sometimes repeat the file name; one line is enough.
std::string oneLine(std::string message) {
    while (!message.empty() && (message.back() == '\n' || message.back() == ' '))
        message.pop_back();
    for (char& c : message)
        if (c == '\n') c = ' ';
    return message.empty() ? "unknown error" : message;
}

} // namespace

int Tool::fail(const std::string& message) const {
    std::fprintf(stderr, "%s: error: %s\n", m_name.c_str(), message.c_str());
    return kExitFailure;
}

void Tool::warn(const std::string& message) const {
    if (!quiet()) std::fprintf(stderr, "%s: warning: %s\n", m_name.c_str(), message.c_str());
}

void Tool::info(const std::string& message) const {
    if (verbose()) std::fprintf(stderr, "%s: %s\n", m_name.c_str(), message.c_str());
}

int Tool::start(const std::vector<std::string>& inputs) const {
    if (m_cl.threads() > 0) OIIO::attribute("threads", m_cl.threads());
    const std::string& out = m_cl.output();
    if (out.empty()) {
        std::fprintf(stderr, "%s: usage error: no output file (-o FILE)\nTry '%s --help'.\n",
                     m_name.c_str(), m_name.c_str());
        return kExitUsage;
    }
    std::error_code ec;
    for (const std::string& in : inputs) {
        if (fs::exists(in, ec) && fs::exists(out, ec) && fs::equivalent(in, out, ec)) {
            fail(out + ": is also an input; refusing to overwrite it");
            return kExitUsage;
        }
    }
    const fs::path folder = fs::absolute(fs::path(out)).parent_path();
    if (!fs::is_directory(folder, ec)) {
        fail(out + ": the folder " + folder.string() + " does not exist");
        return kExitFailure;
    }
    if (access(folder.c_str(), W_OK) != 0) {
        fail(out + ": the folder " + folder.string() + " is not writable");
        return kExitFailure;
    }
    return -1;
}

bool Tool::readImage(const std::string& path, OIIO::ImageBuf& image) const {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
        fail(path + ": no such file");
        return false;
    }
    image.reset(path);
    if (!image.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
        fail(path + ": cannot read: " + oneLine(image.geterror()));
        return false;
    }
    return true;
}

void Tool::replaceNonFinite(const std::string& path, OIIO::ImageBuf& image, int chbegin,
                            int chend) const {
    OIIO::ROI roi = image.roi();
    roi.chbegin = chbegin;
    roi.chend = std::min(chend, image.nchannels());
    const NonFiniteCount n = dhdr::replaceNonFinite(image, roi, threads());
    if (n.total() == 0) return;
    warn(path + ": replaced " + std::to_string(n.total()) + " non-finite values (" +
         std::to_string(n.nan) + " NaN → 0, " + std::to_string(n.positiveInf) +
         " +Inf → largest finite, " + std::to_string(n.negativeInf) + " -Inf → 0)");
}

bool Tool::writeImage(const OIIO::ImageBuf& image, const std::string& path,
                      const std::vector<OIIO::TypeDesc>& formats) const {
    const fs::path target(path);
    // Same folder (so rename is atomic) and same extension (so OIIO picks the format).
    const fs::path temporary =
        target.parent_path() / ("." + target.stem().string() + ".tmp" +
                                std::to_string(getpid()) + target.extension().string());
    std::strncpy(g_temporary, temporary.c_str(), sizeof(g_temporary) - 1);
    std::signal(SIGINT, removeTemporaryAndExit);
    std::signal(SIGTERM, removeTemporaryAndExit);

    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
        g_temporary[0] = 0;
        fail(path + ": cannot write this format: " + oneLine(OIIO::geterror()));
        return false;
    }
    OIIO::ImageSpec spec = image.spec();
    if (formats.size() == 1) {
        spec.set_format(formats[0]);
        spec.channelformats.clear();
    } else if (formats.size() == size_t(spec.nchannels) &&
               out->supports("channelformats")) {
        spec.channelformats = formats;
    } else if (!formats.empty()) {
        spec.set_format(formats[0]);
        spec.channelformats.clear();
    }
    spec.attribute("Software", m_name + " (dhdr " DHDR_VERSION ")");
    const OIIO::ImageBuf pixels = image.spec().format == OIIO::TypeDesc::FLOAT && image.localpixels()
                                      ? OIIO::ImageBuf()
                                      : image.copy(OIIO::TypeDesc::FLOAT);
    const void* data = pixels.initialized() ? pixels.localpixels() : image.localpixels();
    bool ok = out->open(temporary.string(), spec) &&
              out->write_image(OIIO::TypeDesc::FLOAT, data) && out->close();
    std::error_code ec;
    if (ok) {
        fs::rename(temporary, target, ec);
        ok = !ec;
        if (!ok) fail(path + ": cannot move the output into place: " + ec.message());
    } else {
        fail(path + ": cannot write: " + oneLine(out->geterror()));
    }
    if (!ok) fs::remove(temporary, ec);
    g_temporary[0] = 0;
    return ok;
}

Progress::Progress(const Tool& tool, std::string label)
    : m_label(std::move(label)), m_enabled(!tool.quiet() && isatty(STDERR_FILENO)) {}

Progress::~Progress() {
    if (m_enabled && m_percent >= 0) std::fprintf(stderr, "\r%s: done   \n", m_label.c_str());
}

void Progress::update(float fraction) {
    if (!m_enabled) return;
    const int percent = int(fraction * 100.0f);
    if (percent == m_percent.exchange(percent)) return;
    std::lock_guard<std::mutex> lock(m_mutex);
    std::fprintf(stderr, "\r%s: %3d%%", m_label.c_str(), percent);
    std::fflush(stderr);
}

} // namespace dhdr::app
