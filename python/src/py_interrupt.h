// Long calls and Ctrl-C. Python runs its signal handlers only in the main thread and only when
// asked, so a call that releases the GIL for seconds would see Ctrl-C only when it returns.
// The work runs on a thread of its own instead, while the calling thread asks Python every
// 50 ms (PyErr_CheckSignals); when a handler raises (KeyboardInterrupt), the work is told to
// stop through `cancel`, which it polls, is waited for, and the exception is raised: the call
// returns nothing and writes nothing.
#pragma once

#include <atomic>
#include <chrono>
#include <future>
#include <pybind11/pybind11.h>
#include <utility>

namespace dhdr::python {

// Runs `work()`, which must not touch Python (it runs without the GIL), to its end, or raises
// what a signal handler raised once the work has stopped. The work's own exceptions pass.
template <class Work>
void runInterruptibly(std::atomic<bool>& cancel, Work&& work) {
    std::future<void> done;
    {
        pybind11::gil_scoped_release gil;
        done = std::async(std::launch::async, std::forward<Work>(work));
    }
    for (;;) {
        std::future_status status;
        {
            pybind11::gil_scoped_release gil;
            status = done.wait_for(std::chrono::milliseconds(50));
        }
        if (status == std::future_status::ready) break;
        if (PyErr_CheckSignals() != 0) {
            cancel.store(true);
            {
                pybind11::gil_scoped_release gil;
                done.wait();
            }
            throw pybind11::error_already_set();
        }
    }
    done.get();
}

} // namespace dhdr::python
