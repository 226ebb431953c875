// The two forms of every image operation, as OpenImageIO's Python bindings have them:
// op(dst, src, *, ..., roi=None, nthreads=0) -> bool and op(src, *, ..., roi=None, nthreads=0)
// -> Image, with the GIL released around the library call.
#pragma once

#include "py_image.h"

#include <atomic>
#include <dhdr/common/param_table.h>
#include <functional>

namespace dhdr::python {

// A library call on prepared parameters: dst (uninitialized, or the caller's pixels), src, roi,
// nthreads. Runs without the GIL: it must touch no Python object.
using ImageOp = std::function<bool(OIIO::ImageBuf&, const OIIO::ImageBuf&, OIIO::ROI, int)>;

// A call that may run for seconds (light(gi='path')): it runs on a thread of its own and stops
// when `cancel` is set, which Ctrl-C does (py_interrupt.h); the call then raises
// KeyboardInterrupt and writes nothing into dst.
struct LongOp {
    std::function<bool(OIIO::ImageBuf&, const OIIO::ImageBuf&, OIIO::ROI, int,
                       const std::atomic<bool>& cancel)>
        run;
};

// The result as a new Image; the library's error as RuntimeError.
Image runNew(const Image& src, OIIO::ROI roi, int nthreads, const ImageOp& op);
Image runNew(const Image& src, OIIO::ROI roi, int nthreads, const LongOp& op);

// Into `dst`'s own pixels when it has writable ones (only `roi` written, as in OpenImageIO),
// else into new pixels. src is copied first when it shares dst's memory. False with
// dst.geterror() when the library fails.
bool runInto(Image& dst, const Image& src, OIIO::ROI roi, int nthreads, const ImageOp& op);
bool runInto(Image& dst, const Image& src, OIIO::ROI roi, int nthreads, const LongOp& op);

// Registers both forms of `name`. src's NaN and ±Inf are read as the tools read them
// (finiteImage), on a copy. `prepare(src, args...)` turns the keyword arguments into the
// call (raising ValueError for bad ones) with the GIL held; `extra` are their py::arg's, from
// py::kw_only() on keyword-only (light's lights come before it: light(gbuffer, lights)).
template <class Op, class... Args, class... Extra>
void defImageOp(py::module_& m, const char* name, const char* doc,
                Op (*prepare)(const Image&, Args...), const Extra&... extra) {
    // The return form first: op(src, lights) must not be taken for op(dst, src) when an
    // argument after src may be positional (light's lights); op(dst, src, ...) has one
    // positional argument too many for it.
    m.def(
        name,
        [prepare](const py::object& src, Args... args, const py::object& roi, int nthreads) {
            Image storage;
            Image finite;
            const Image& in = finiteImage(asImage(src, "src", storage), "src", finite);
            const Op op = prepare(in, args...);
            return runNew(in, toRoi(roi), nthreads, op);
        },
        py::arg("src"), extra..., py::arg("roi") = py::none(), py::arg("nthreads") = 0, doc);
    m.def(
        name,
        [prepare](Image& dst, const py::object& src, Args... args, const py::object& roi,
                  int nthreads) {
            Image storage;
            Image finite;
            const Image& in = finiteImage(asImage(src, "src", storage), "src", finite);
            const Op op = prepare(in, args...);
            return runInto(dst, in, toRoi(roi), nthreads, op);
        },
        py::arg("dst"), py::arg("src"), extra..., py::arg("roi") = py::none(),
        py::arg("nthreads") = 0, doc);
}

// Raises ValueError naming the first keyword of `params` outside its range in `table` (the
// library's, where the tools' options come from).
template <class Params, class Table>
void checkParams(const Params& params, const Table& table) {
    if (const std::string e = checkRanges(params, table, Spelling::Keyword); !e.empty())
        throw py::value_error(e);
}

} // namespace dhdr::python
