#include "tool.h"

#include "frames.h"
#include "layers.h"
#include "native_pixels.h"

#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <csignal>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <dhdr/deferred/deep_exr.h>
#include <dhdr/deferred/exr_header.h>
#include <dhdr/tonemap/sanitize.h>
#include <filesystem>
#include <fstream>
#include <future>
#include <new>
#include <sys/types.h>
#include <system_error>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;

namespace dhdr::app {

namespace {

// Every temporary output open in the process (frames of a sequence are written in
// parallel), in fixed slots that a signal handler can read without locks or allocation.
class TemporaryRegistry {
public:
    static TemporaryRegistry& instance() {
        static TemporaryRegistry registry;
        return registry;
    }

    void add(const std::string& path) {
        std::lock_guard<std::mutex> lock(m_mutex);
        installHandlers();
        for (Slot& s : m_slots) {
            if (s.used.load(std::memory_order_relaxed)) continue;
            std::strncpy(s.path, path.c_str(), sizeof(s.path) - 1);
            s.path[sizeof(s.path) - 1] = 0;
            s.used.store(true, std::memory_order_release);
            return;
        }
        // More outputs open at once than slots: not removed on a signal, still on failure.
    }

    void remove(const std::string& path) {
        std::lock_guard<std::mutex> lock(m_mutex);
        for (Slot& s : m_slots)
            if (s.used.load(std::memory_order_relaxed) && path == s.path)
                s.used.store(false, std::memory_order_release);
    }

    // Async-signal-safe: unlink is, and the slots are only read.
    void unlinkAll() {
        for (Slot& s : m_slots)
            if (s.used.load(std::memory_order_acquire)) unlink(s.path);
    }

private:
    struct Slot {
        std::atomic<bool> used{false};
        char path[4096] = {0};
    };

    static void onSignal(int signal) {
        instance().unlinkAll();
        std::signal(signal, SIG_DFL);
        std::raise(signal);
    }

    // A termination signal that the process was started with ignored stays ignored, as
    // well-behaved Unix tools do: `nohup dhdr-… &` ignores SIGHUP, and a shell without job
    // control starts `dhdr-… &` with SIGINT and SIGQUIT ignored; such a run must go on, not
    // die in our handler. Fatal signals (SIGABRT from abort(), and the faults) end the
    // process whatever their disposition, so their handler is always installed to clean up.
    void installHandlers() {
        if (m_installed) return;
        m_installed = true;
        struct sigaction action {};
        action.sa_handler = onSignal;
        sigemptyset(&action.sa_mask);
        action.sa_flags = SA_RESTART; // as signal() installs a handler
        for (int s : {SIGHUP, SIGINT, SIGTERM, SIGQUIT}) {
            struct sigaction old {};
            if (sigaction(s, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
            sigaction(s, &action, nullptr);
        }
        for (int s : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL})
            sigaction(s, &action, nullptr);
    }

    std::mutex m_mutex;
    bool m_installed = false;
    Slot m_slots[64];
};

// ".NAME.tmpPID.EXT": where a temporary of `target` written by process `pid` lives.
fs::path temporaryFor(const fs::path& target, pid_t pid) {
    return target.parent_path() / ("." + target.stem().string() + ".tmp" + std::to_string(pid) +
                                   target.extension().string());
}

// Removes temporaries of `target` whose writer is gone (killed by SIGKILL, or a crash the
// handlers could not see); a live process's are left alone.
void removeStaleTemporaries(const fs::path& target) {
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    const std::string head = "." + target.stem().string() + ".tmp";
    const std::string tail = target.extension().string();
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() <= head.size() + tail.size() || name.rfind(head, 0) != 0 ||
            name.compare(name.size() - tail.size(), tail.size(), tail) != 0)
            continue;
        const std::string digits =
            name.substr(head.size(), name.size() - head.size() - tail.size());
        if (digits.empty() || digits.size() > 9 ||
            digits.find_first_not_of("0123456789") != std::string::npos)
            continue;
        const pid_t pid = pid_t(std::stol(digits));
        if (pid == getpid() || kill(pid, 0) == 0 || errno != ESRCH) continue;
        fs::remove(entry.path(), ec);
    }
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

std::string cannotRead(const std::string& path, const std::string& error) {
    if (path.find('?') != std::string::npos &&
        error.find("malformed filename") != std::string::npos)
        return path + ": cannot read: OpenImageIO takes what follows '?' in a file name for "
                      "options (file.exr?key=value); rename the file without '?'";
    return path + (isPixelLimitError(error) ? ": " : ": cannot read: ") + oneLine(error);
}

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

int Tool::start(const std::vector<std::string>& inputs, const std::string& out) const {
    const int threads = m_cl.threads() > 0 ? m_cl.threads()
                                           : int(std::max(1u, std::thread::hardware_concurrency()));
    OIIO::attribute("threads", threads);
    // OpenEXR's own pool (compression and decompression of line blocks) is separate, and
    // left at its default it does not run in parallel.
    OIIO::attribute("exr_threads", threads);
    if (out.empty()) {
        std::fprintf(stderr, "%s: usage error: no output file (-o FILE)\nTry '%s --help'.\n",
                     m_name.c_str(), m_name.c_str());
        return kExitUsage;
    }
    std::vector<NamedFile> in, outs;
    files(inputs, out, in, outs);
    for (const auto* list : {&in, &outs})
        for (const NamedFile& f : *list)
            if (FramePattern(f.path).width() > kMaxFrameWidth) {
                std::fprintf(stderr,
                             "%s: usage error: %s: the frame pattern is wider than %d digits "
                             "(frame numbers have at most 9)\n",
                             m_name.c_str(), f.path.c_str(), kMaxFrameWidth);
                return kExitUsage;
            }
    // OpenImageIO reads what follows a '?' in an image's name as options (file.exr?key=value)
    // and refuses the name otherwise: an image written under it could never be read back.
    for (const NamedFile& f : outs) {
        std::string ext = fs::path(f.path).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
        if (f.path.find('?') != std::string::npos && ext != ".json") {
            std::fprintf(stderr,
                         "%s: usage error: %s: an image whose name holds '?' cannot be read back "
                         "(OpenImageIO takes what follows '?' for options: file.exr?key=value); "
                         "choose a name without '?'\n",
                         m_name.c_str(), f.path.c_str());
            return kExitUsage;
        }
    }
    if (!outputsAreTheirOwn(in, outs)) return kExitUsage;
    std::error_code ec;
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

void Tool::files(const std::vector<std::string>& inputs, const std::string& out,
                 std::vector<NamedFile>& in, std::vector<NamedFile>& outs) const {
    in = m_cl.inputFiles();
    for (const std::string& path : inputs)
        if (std::none_of(in.begin(), in.end(), [&](const NamedFile& f) { return f.path == path; }))
            in.push_back({"", path});
    outs.clear();
    if (!m_cl.output().empty()) outs.push_back({"-o", m_cl.output()});
    for (const NamedFile& f : m_cl.outputFiles())
        outs.push_back(f);
    if (!out.empty() &&
        std::none_of(outs.begin(), outs.end(), [&](const NamedFile& f) { return f.path == out; }))
        outs.push_back({"the output", out});
}

namespace {

// Whether `a` and `b` are one file: by identity (a hard link, a symbolic link, another
// spelling) when both exist; else by their paths made absolute, with symbolic links in the
// folders that exist resolved, and normalized (./x.exr and d/../x.exr are x.exr).
bool sameFile(const std::string& a, const std::string& b) {
    if (a == b) return true;
    std::error_code ea, eb;
    const bool aExists = fs::exists(a, ea), bExists = fs::exists(b, eb);
    if (aExists && bExists) return fs::equivalent(a, b, ea) && !ea;
    if (aExists != bExists) return false;
    fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
    if (ea) ca = fs::absolute(a, ea).lexically_normal();
    if (eb) cb = fs::absolute(b, eb).lexically_normal();
    return ca == cb;
}

} // namespace

bool Tool::outputsAreTheirOwn(const std::vector<NamedFile>& inputs,
                              const std::vector<NamedFile>& outputs) const {
    for (size_t o = 0; o < outputs.size(); ++o) {
        const NamedFile& out = outputs[o];
        for (const NamedFile& in : inputs)
            if (sameFile(in.path, out.path)) {
                fail(out.path + ": the output (" + out.option + ") is also an input" +
                     (in.option.empty() ? "" : " (" + in.option + ")") +
                     "; refusing to overwrite it");
                return false;
            }
        for (size_t k = 0; k < o; ++k)
            if (sameFile(outputs[k].path, out.path)) {
                fail(out.path + ": " + outputs[k].option + " and " + out.option +
                     " name the same file; give each output its own");
                return false;
            }
    }
    return true;
}

namespace {

// The colour layer of `path` a tool works on, after printing why there is none.
bool findColour(const Tool& tool, const std::string& path, const std::string& layer,
                ColourLayer& chosen) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
        tool.fail(path + ": no such file");
        return false;
    }
    std::vector<ColourLayer> layers;
    std::string error;
    // Before OpenEXR allocates what its headers claim (frames.cpp does the same per frame).
    if (!detail::exrHeadersFit(path, error)) {
        tool.fail(path + ": " + error);
        return false;
    }
    if (!listColourLayers(path, layers, error)) {
        tool.fail(cannotRead(path, error));
        return false;
    }
    if (!chooseColourLayer(layers, layer, chosen, error)) {
        tool.fail(path + ": " + error);
        return false;
    }
    // Before any pixel is read or any output opened.
    if (const std::string e = pixelLimitError(chosen.width, chosen.height, chosen.depth);
        !e.empty()) {
        tool.fail(path + ": " + e);
        return false;
    }
    if (layers.size() > 1 || chosen.subimage > 0)
        tool.info(path + ": reading layer '" + chosen.name() + "'");
    return true;
}

} // namespace

bool Tool::openColour(const std::string& path, const std::string& layer, bool keepOthers,
                      ColourStripReader& reader) const {
    ColourLayer chosen;
    if (!findColour(*this, path, layer, chosen)) return false;
    std::string error;
    if (!reader.open(path, chosen, keepOthers, threads(), error)) {
        fail(cannotRead(path, error));
        return false;
    }
    return true;
}

bool Tool::readColour(const std::string& path, const std::string& layer, bool keepOthers,
                      OIIO::ImageBuf& image, std::vector<OIIO::TypeDesc>& formats,
                      int nthreads) const {
    ColourLayer chosen;
    if (!findColour(*this, path, layer, chosen)) return false;
    std::string error;
    if (!readColourLayer(path, chosen, keepOthers, nthreads, image, formats, error)) {
        fail(cannotRead(path, error));
        return false;
    }
    return true;
}

bool hasSurface(const OIIO::ImageBuf& image, OIIO::ROI roi) {
    if (image.spec().alpha_channel != 3 || !image.localpixels()) return true;
    roi = OIIO::roi_intersection(roi.defined() ? roi : image.roi(), image.roi());
    for (int y = roi.ybegin; y < roi.yend; ++y)
        for (int x = roi.xbegin; x < roi.xend; ++x)
            if (static_cast<const float*>(image.pixeladdr(x, y))[3] != 0.0f) return true;
    return false;
}

void Tool::warnNoSurface(const std::string& path) const {
    warn(path + ": no surface in view: alpha is 0 everywhere (an empty frame)");
}

void Tool::reportNonFinite(const std::string& path, const NonFiniteCount& n,
                           bool zeroNegative) const {
    if (n.total() == 0) return;
    const std::string what =
        zeroNegative ? " non-finite or negative values (" : " non-finite values (";
    warn(path + ": replaced " + std::to_string(n.total()) + what + std::to_string(n.nan) +
         " NaN → 0, " + std::to_string(n.positiveInf) + " +Inf → 65504, " +
         std::to_string(n.negativeInf) + " -Inf → 0" +
         (zeroNegative ? ", " + std::to_string(n.negative) + " negative → 0)" : ")"));
}

bool Tool::writeAtomically(
    const std::string& path,
    const std::function<bool(const std::string&, std::string&)>& write) const {
    const fs::path target(path);
    removeStaleTemporaries(target);
    const fs::path temporary = temporaryFor(target, getpid());
    TemporaryRegistry::instance().add(temporary.string());
    std::error_code ec;
    std::string error;
    if (!write(temporary.string(), error)) {
        fs::remove(temporary, ec);
        TemporaryRegistry::instance().remove(temporary.string());
        fail(path + ": cannot write" + (error.empty() ? "" : ": " + error));
        return false;
    }
    fs::rename(temporary, target, ec);
    TemporaryRegistry::instance().remove(temporary.string());
    if (ec) {
        fs::remove(temporary, ec);
        fail(path + ": cannot move the output into place: " + ec.message());
        return false;
    }
    return true;
}

bool Tool::writeText(const std::string& text, const std::string& path) const {
    return writeAtomically(path, [&](const std::string& temporary, std::string&) {
        std::ofstream out(temporary, std::ios::binary);
        out << text;
        return bool(out.flush());
    });
}

AtomicOutput::AtomicOutput(const Tool& tool, std::string path)
    : m_tool(tool), m_path(std::move(path)) {
    const fs::path target(m_path);
    removeStaleTemporaries(target);
    // Frames of a sequence written at once by one process have different targets, so the
    // process id keeps temporaries apart.
    m_temporary = temporaryFor(target, getpid()).string();
}

AtomicOutput::~AtomicOutput() {
    if (m_committed) return;
    if (m_out) m_out->close();
    m_deep.reset();
    std::error_code ec;
    fs::remove(m_temporary, ec);
    TemporaryRegistry::instance().remove(m_temporary);
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
    // Scanline output whatever the input was (a tiled input's spec carries its tiling, which
    // the scanline writes below cannot fill), one part, flat.
    spec.tile_width = spec.tile_height = spec.tile_depth = 0;
    spec.deep = false;
    spec.erase_attribute("oiio:subimages");
    bool native = true;
    for (int c = 0; c < spec.nchannels; ++c) {
        const OIIO::TypeDesc t = spec.channelformat(c);
        native = native && (t == OIIO::TypeDesc::HALF || t == OIIO::TypeDesc::FLOAT ||
                            t == OIIO::TypeDesc::UINT);
    }
    const int z = spec.channelindex("Z");
    m_native = native ? std::make_unique<NativeWriter>(spec, z) : nullptr;
    return openTemporary(spec);
}

bool AtomicOutput::openTemporary(const OIIO::ImageSpec& spec) {
    TemporaryRegistry::instance().add(m_temporary);
    if (!m_out->open(m_temporary, spec)) {
        m_tool.fail(m_path + ": cannot write: " + oneLine(m_out->geterror()));
        m_out.reset();
        return false;
    }
    return true;
}

bool AtomicOutput::openDeep(OIIO::ImageSpec spec) {
    std::string ext = fs::path(m_path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext != ".exr") {
        m_tool.fail(m_path + ": cannot write deep images in this format (use .exr)");
        return false;
    }
    spec.attribute("Software", m_tool.name() + " (dhdr " DHDR_VERSION ")");
    spec.tile_width = spec.tile_height = spec.tile_depth = 0;
    spec.deep = true;
    TemporaryRegistry::instance().add(m_temporary);
    m_deep = std::make_unique<DeepScanlineWriter>();
    if (std::string error; !m_deep->open(m_temporary, spec, error)) {
        m_tool.fail(m_path + ": cannot write: " + oneLine(error));
        m_deep.reset();
        return false;
    }
    return true;
}

bool AtomicOutput::writeDeepRows(int ybegin, int yend, const OIIO::DeepData& samples) {
    // The flat output's rule for every sample: NaN becomes 0, ±Inf (a half channel's overflow
    // included, when the value was stored) the type's largest finite value, counted.
    std::unique_ptr<OIIO::DeepData> fixed;
    for (int64_t p = 0; p < samples.pixels(); ++p)
        for (int c = 0; c < samples.channels(); ++c)
            for (int k = 0; k < samples.samples(p); ++k) {
                const float v = samples.deep_value(p, c, k);
                if (std::isfinite(v)) continue;
                if (!fixed) fixed = std::make_unique<OIIO::DeepData>(samples);
                const float largest =
                    samples.channeltype(c) == OIIO::TypeDesc::HALF ? 65504.0f : FLT_MAX;
                fixed->set_deep_value(p, c, k, std::isnan(v) ? 0.0f : std::copysign(largest, v));
                ++(std::isnan(v) ? m_nonFinite : m_clamped);
            }
    if (std::string error; !m_deep->write(ybegin, yend, fixed ? *fixed : samples, error)) {
        m_tool.fail(m_path + ": cannot write: " + oneLine(error));
        return false;
    }
    return true;
}

bool AtomicOutput::writeRows(int ybegin, int yend, const float* pixels) {
    const OIIO::ImageSpec& spec = m_out->spec();
    const size_t count = size_t(yend - ybegin) * size_t(spec.width);
    bool written = false;
    if (m_native) {
        // In the file's own types, so that uint channels hold integers rather than OIIO's
        // float-to-uint scaling of [0, 1] to [0, 2^32 − 1].
        m_buffer.resize(count * m_native->pixelBytes());
        m_native->convert(pixels, count, m_buffer.data(), m_clamped, m_nonFinite);
        written = m_out->write_scanlines(ybegin, yend, 0, OIIO::TypeUnknown, m_buffer.data());
    } else {
        // Integer formats: OIIO's conversion clamps to their range; NaN only needs replacing.
        std::vector<float> copy(pixels, pixels + count * size_t(spec.nchannels));
        for (float& v : copy)
            if (std::isnan(v)) {
                v = 0.0f;
                ++m_nonFinite;
            }
        written = m_out->write_scanlines(ybegin, yend, 0, OIIO::TypeDesc::FLOAT, copy.data());
    }
    if (!written) {
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
        if (type == OIIO::TypeDesc::FLOAT) {
            if (!writeRows(r.ybegin, r.yend, reinterpret_cast<const float*>(buffers[k % 2].data())))
                return false;
            continue;
        }
        if (!m_out->write_scanlines(r.ybegin, r.yend, 0, type, buffers[k % 2].data())) {
            m_tool.fail(m_path + ": cannot write: " + oneLine(m_out->geterror()));
            return false;
        }
    }
    return true;
}

bool AtomicOutput::commit() {
    if (m_deep) {
        if (std::string error; !m_deep->close(error)) {
            m_tool.fail(m_path + ": cannot write: " + oneLine(error));
            return false;
        }
        m_deep.reset();
    } else if (!m_out->close()) {
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
    TemporaryRegistry::instance().remove(m_temporary);
    if (m_nonFinite > 0)
        m_tool.warn(m_path + ": wrote " + std::to_string(m_nonFinite) +
                    " non-finite values as finite ones (NaN → 0, ±Inf → the largest float)");
    if (m_clamped > 0)
        m_tool.warn(m_path + ": " + std::to_string(m_clamped) +
                    " values beyond half float's ±65504 were clamped to it; write float to keep "
                    "them (dhdr-light --type float)");
    return true;
}

int guardedMain(const char* name, const std::function<int()>& body) {
    try {
        return body();
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "%s: error: out of memory\n", name);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: error: %s\n", name, oneLine(e.what()).c_str());
    } catch (...) {
        std::fprintf(stderr, "%s: error: unexpected failure\n", name);
    }
    return kExitFailure;
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
