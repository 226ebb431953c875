#include "tool.h"

#include "banded_read.h"

#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <csignal>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <dhdr/tonemap/sanitize.h>
#include <filesystem>
#include <fstream>
#include <future>
#include <system_error>
#include <thread>
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
    const int threads = m_cl.threads() > 0 ? m_cl.threads()
                                           : int(std::max(1u, std::thread::hardware_concurrency()));
    OIIO::attribute("threads", threads);
    // OpenEXR's own pool (compression and decompression of line blocks) is separate, and
    // left at its default it does not run in parallel.
    OIIO::attribute("exr_threads", threads);
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

bool Tool::readImage(const std::string& path, OIIO::ImageBuf& image, int nthreads) const {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
        fail(path + ": no such file");
        return false;
    }
    std::string error;
    if (!readBanded(path, image, 0, 1 << 20, nthreads, error)) {
        fail(path + ": cannot read: " + oneLine(error));
        return false;
    }
    return true;
}

bool Tool::readImageChannels(const std::string& path, const std::vector<std::string>& names,
                             OIIO::ImageBuf& image) const {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
        fail(path + ": no such file");
        return false;
    }
    image.reset(path);
    if (!image.init_spec(path, 0, 0)) {
        fail(path + ": cannot read: " + oneLine(image.geterror()));
        return false;
    }
    int chbegin = image.nchannels(), chend = 0;
    for (const std::string& name : names) {
        const int c = image.spec().channelindex(name);
        if (c < 0) continue;
        chbegin = std::min(chbegin, c);
        chend = std::max(chend, c + 1);
    }
    if (chend <= chbegin) chbegin = 0, chend = image.nchannels();
    std::string error;
    if (!readBanded(path, image, chbegin, chend, threads(), error)) {
        fail(path + ": cannot read: " + oneLine(error));
        return false;
    }
    return true;
}

void Tool::replaceNonFinite(const std::string& path, OIIO::ImageBuf& image, int chbegin, int chend,
                            bool zeroNegative) const {
    OIIO::ROI roi = image.roi();
    roi.chbegin = chbegin;
    roi.chend = std::min(chend, image.nchannels());
    reportNonFinite(path, dhdr::replaceNonFinite(image, roi, threads(), zeroNegative),
                    zeroNegative);
}

void Tool::reportNonFinite(const std::string& path, const NonFiniteCount& n,
                           bool zeroNegative) const {
    if (n.total() == 0) return;
    const std::string what =
        zeroNegative ? " non-finite or negative values (" : " non-finite values (";
    warn(path + ": replaced " + std::to_string(n.total()) + what + std::to_string(n.nan) +
         " NaN → 0, " + std::to_string(n.positiveInf) + " +Inf → largest finite, " +
         std::to_string(n.negativeInf) + " -Inf → 0" +
         (zeroNegative ? ", " + std::to_string(n.negative) + " negative → 0)" : ")"));
}

bool Tool::writeImage(const OIIO::ImageBuf& image, const std::string& path,
                      const std::vector<OIIO::TypeDesc>& formats) const {
    const OIIO::ImageBuf copy = image.spec().format == OIIO::TypeDesc::FLOAT && image.localpixels()
                                    ? OIIO::ImageBuf()
                                    : image.copy(OIIO::TypeDesc::FLOAT);
    const OIIO::ImageBuf& pixels = copy.initialized() ? copy : image;
    AtomicOutput out(*this, path);
    if (!out.open(pixels.spec(), formats)) return false;
    // In strips, which keeps the conversion to file types in cache.
    constexpr int kStrip = 64;
    const OIIO::ROI roi = pixels.roi();
    for (int y = roi.ybegin; y < roi.yend; y += kStrip) {
        const auto* rows = static_cast<const float*>(pixels.pixeladdr(roi.xbegin, y));
        if (!out.writeRows(y, std::min(y + kStrip, roi.yend), rows)) return false;
    }
    return out.commit();
}

bool Tool::writeText(const std::string& text, const std::string& path) const {
    const fs::path target(path);
    const fs::path temporary = target.parent_path() / ("." + target.filename().string() + ".tmp" +
                                                       std::to_string(getpid()));
    std::error_code ec;
    {
        std::ofstream out(temporary, std::ios::binary);
        out << text;
        if (!out.flush()) {
            fs::remove(temporary, ec);
            fail(path + ": cannot write");
            return false;
        }
    }
    fs::rename(temporary, target, ec);
    if (ec) {
        fs::remove(temporary, ec);
        fail(path + ": cannot move the output into place: " + ec.message());
        return false;
    }
    return true;
}

AtomicOutput::AtomicOutput(const Tool& tool, std::string path)
    : m_tool(tool), m_path(std::move(path)) {
    const fs::path target(m_path);
    m_temporary = (target.parent_path() / ("." + target.stem().string() + ".tmp" +
                                           std::to_string(getpid()) + target.extension().string()))
                      .string();
}

AtomicOutput::~AtomicOutput() {
    if (m_committed) return;
    if (m_out) m_out->close();
    std::error_code ec;
    fs::remove(m_temporary, ec);
    g_temporary[0] = 0;
}

bool AtomicOutput::open(OIIO::ImageSpec spec, const std::vector<OIIO::TypeDesc>& formats) {
    m_out = OIIO::ImageOutput::create(m_path);
    if (!m_out) {
        m_tool.fail(m_path + ": cannot write this format: " + oneLine(OIIO::geterror()));
        return false;
    }
    if (formats.size() == size_t(spec.nchannels) && formats.size() > 1 &&
        m_out->supports("channelformats")) {
        spec.channelformats = formats;
    } else {
        spec.set_format(formats.empty() ? OIIO::TypeDesc::FLOAT : formats[0]);
        spec.channelformats.clear();
    }
    spec.attribute("Software", m_tool.name() + " (dhdr " DHDR_VERSION ")");
    if (!m_tool.commandLine().compression().empty())
        spec.attribute("compression", m_tool.commandLine().compression());
    std::strncpy(g_temporary, m_temporary.c_str(), sizeof(g_temporary) - 1);
    std::signal(SIGINT, removeTemporaryAndExit);
    std::signal(SIGTERM, removeTemporaryAndExit);
    if (!m_out->open(m_temporary, spec)) {
        m_tool.fail(m_path + ": cannot write: " + oneLine(m_out->geterror()));
        m_out.reset();
        return false;
    }
    return true;
}

bool AtomicOutput::writeRows(int ybegin, int yend, const float* pixels) {
    if (!m_out->write_scanlines(ybegin, yend, 0, OIIO::TypeDesc::FLOAT, pixels)) {
        m_tool.fail(m_path + ": cannot write: " + oneLine(m_out->geterror()));
        return false;
    }
    return true;
}

bool AtomicOutput::writeStrips(OIIO::TypeDesc type, int rows, bool overlap, const StripFill& fill) {
    const OIIO::ImageSpec& spec = m_out->spec();
    const int strips = (spec.height + rows - 1) / rows;
    const size_t stripBytes =
        size_t(rows) * size_t(spec.width) * size_t(spec.nchannels) * type.size();
    std::vector<std::byte> buffers[2] = {std::vector<std::byte>(stripBytes),
                                         std::vector<std::byte>(stripBytes)};
    auto strip = [&](int k) {
        const int y0 = spec.y + k * rows;
        return OIIO::ROI(spec.x, spec.x + spec.width, y0, std::min(y0 + rows, spec.y + spec.height),
                         0, 1, 0, spec.nchannels);
    };
    auto compute = [&](int k) {
        return std::async(overlap ? std::launch::async : std::launch::deferred,
                          [&, k] { return fill(strip(k), buffers[k % 2].data()); });
    };
    std::future<bool> next = compute(0);
    for (int k = 0; k < strips; ++k) {
        if (!next.get()) return false;
        if (k + 1 < strips) next = compute(k + 1);
        const OIIO::ROI r = strip(k);
        if (!m_out->write_scanlines(r.ybegin, r.yend, 0, type, buffers[k % 2].data())) {
            m_tool.fail(m_path + ": cannot write: " + oneLine(m_out->geterror()));
            return false;
        }
    }
    return true;
}

bool AtomicOutput::commit() {
    if (!m_out->close()) {
        m_tool.fail(m_path + ": cannot write: " + oneLine(m_out->geterror()));
        return false;
    }
    m_out.reset();
    std::error_code ec;
    fs::rename(m_temporary, m_path, ec);
    if (ec) {
        m_tool.fail(m_path + ": cannot move the output into place: " + ec.message());
        return false;
    }
    m_committed = true;
    g_temporary[0] = 0;
    return true;
}

Progress::Progress(const Tool& tool, std::string label)
    : m_label(std::move(label)), m_enabled(!tool.quiet() && isatty(STDERR_FILENO)) {}

Progress::~Progress() {
    if (m_enabled && m_percent >= 0) std::fprintf(stderr, "\r%s: done   \n", m_label.c_str());
}

void Progress::update(float fraction, const std::string& detail) {
    if (!m_enabled) return;
    const int percent = int(fraction * 100.0f);
    if (percent == m_percent.exchange(percent)) return;
    std::lock_guard<std::mutex> lock(m_mutex);
    std::fprintf(stderr, "\r%s: %3d%% %s", m_label.c_str(), percent, detail.c_str());
    std::fflush(stderr);
}

} // namespace dhdr::app
