#include "temporary_files.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <mutex>
#include <signal.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace dhdr::detail {

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
public:
    void installHandlers() {
        std::lock_guard<std::mutex> lock(m_mutex);
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

private:
    std::mutex m_mutex;
    bool m_installed = false;
    Slot m_slots[64];
};

} // namespace

void registerTemporary(const std::string& path) {
    TemporaryRegistry::instance().add(path);
}

void unregisterTemporary(const std::string& path) {
    TemporaryRegistry::instance().remove(path);
}

void installTemporaryHandlers() {
    TemporaryRegistry::instance().installHandlers();
}

fs::path temporaryFor(const fs::path& target, pid_t pid) {
    return target.parent_path() / ("." + target.stem().string() + ".tmp" + std::to_string(pid) +
                                   target.extension().string());
}

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

} // namespace dhdr::detail
