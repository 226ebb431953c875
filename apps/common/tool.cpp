#include "tool.h"

#include "frames.h"

#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <dhdr/io/deep_exr.h>
#include <dhdr/io/exr_header.h>
#include <dhdr/io/layers.h>
#include <dhdr/io/pixel_limit.h>
#include <dhdr/io/sanitize.h>
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

void Tool::say(const std::vector<std::string>& warnings,
               const std::vector<std::string>& notes) const {
    for (const std::string& w : warnings)
        warn(w);
    for (const std::string& n : notes)
        info(n);
}

namespace {

// How many threads can run at once, up to `wanted`. OpenImageIO's pool, asked for more than can
// start, throws and is left with empty slots that crash the process at exit.
int startableThreads(int wanted) {
    std::vector<std::thread> probe;
    try {
        while (int(probe.size()) < wanted)
            probe.emplace_back([] {});
    } catch (const std::system_error&) {
    }
    for (std::thread& t : probe)
        t.join();
    return int(probe.size());
}

} // namespace

int Tool::start(const std::vector<std::string>& inputs, const std::string& out) const {
    int threads = m_cl.threads() > 0 ? m_cl.threads()
                                     : int(std::max(1u, std::thread::hardware_concurrency()));
    // OpenImageIO's and OpenEXR's pools take a thread each per --threads, Embree's more.
    if (const int startable = startableThreads(4 * threads); startable < 4 * threads) {
        const int fewer = std::max(1, startable / 4);
        warn("only " + std::to_string(startable) +
             " threads could start (is the address space "
             "limited? ulimit -v): running " +
             std::to_string(fewer) + " rather than " + std::to_string(threads) +
             "; the results are the same");
        threads = fewer;
        m_threads = fewer;
    }
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
    size_t layers = 0;
    if (std::string error; !findColourLayer(path, layer, chosen, layers, error)) {
        tool.fail(error);
        return false;
    }
    if (layers > 1 || chosen.subimage > 0)
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

int Tool::findPart(const std::string& path,
                   const std::function<bool(const OIIO::ImageSpec&)>& wanted,
                   OIIO::ImageSpec& spec) const {
    if (!std::filesystem::exists(path)) {
        fail(path + ": no such file");
        return -1;
    }
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
    if (!in) {
        fail(path + ": cannot read: " + OIIO::geterror());
        return -1;
    }
    int part = 0;
    for (int s = 0; in->seek_subimage(s, 0); ++s)
        if (wanted(in->spec())) {
            part = s;
            break;
        }
    in->seek_subimage(part, 0);
    spec = in->spec();
    if (const std::string e = pixelLimitError(spec.width, spec.height, spec.depth); !e.empty()) {
        fail(path + ": " + e);
        return -1;
    }
    return part;
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
    std::string error;
    if (writeFileAtomically(path, write, error)) return true;
    fail(error);
    return false;
}

bool Tool::writeText(const std::string& text, const std::string& path) const {
    return writeAtomically(path, [&](const std::string& temporary, std::string&) {
        std::ofstream out(temporary, std::ios::binary);
        out << text;
        return bool(out.flush());
    });
}

namespace {

ImageOutputOptions outputOptions(const Tool& tool) {
    ImageOutputOptions options;
    options.software = tool.name() + " (dhdr " DHDR_VERSION ")";
    options.compression = tool.commandLine().compression();
    return options;
}

} // namespace

AtomicOutput::AtomicOutput(const Tool& tool, std::string path)
    : m_tool(tool), m_file(std::move(path), outputOptions(tool)) {}

bool AtomicOutput::report(bool ok) const {
    if (!ok) m_tool.fail(m_file.geterror());
    return ok;
}

bool AtomicOutput::commit() {
    if (!report(m_file.commit())) return false;
    for (const std::string& w : m_file.warnings())
        m_tool.warn(w);
    return true;
}

int guardedMain(const char* name, const std::function<int()>& body) {
    removeTemporaryOutputsOnSignals();
    try {
        return body();
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "%s: error: out of memory\n", name);
    } catch (const std::system_error& e) {
        if (e.code() == std::errc::resource_unavailable_try_again)
            std::fprintf(stderr,
                         "%s: error: cannot start a thread (%s): is the address space limited "
                         "(ulimit -v)? give fewer --threads\n",
                         name, e.what());
        else
            std::fprintf(stderr, "%s: error: %s\n", name, oneLine(e.what()).c_str());
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

void Progress::update(float fraction, long long done, long long total, const char* items) {
    if (!m_enabled) return;
    const int percent = int(fraction * 100.0f);
    const long long now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                              std::chrono::steady_clock::now().time_since_epoch())
                              .count();
    const bool newPercent = percent != m_percent.exchange(percent);
    long long printed = m_printedAt.load();
    if (!newPercent &&
        (now - printed < 500000000LL || !m_printedAt.compare_exchange_strong(printed, now)))
        return;
    m_printedAt.store(now);
    std::lock_guard<std::mutex> lock(m_mutex);
    std::fprintf(stderr, "\r%s: %3d%% (%lld of %lld %s)  ", m_label.c_str(), percent, done, total,
                 items);
    std::fflush(stderr);
}

} // namespace dhdr::app
