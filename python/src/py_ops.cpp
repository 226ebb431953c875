#include "py_ops.h"

#include "py_interrupt.h"

#include <cstring>

namespace dhdr::python {

namespace {

// The call without the GIL.
bool invoke(const ImageOp& op, OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi,
            int nthreads) {
    py::gil_scoped_release gil;
    return op(dst, src, roi, nthreads);
}

// On a thread of its own, stopped by Ctrl-C (KeyboardInterrupt raised once it has stopped).
bool invoke(const LongOp& op, OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi,
            int nthreads) {
    std::atomic<bool> cancel{false};
    bool ok = false;
    runInterruptibly(cancel, [&] { ok = op.run(dst, src, roi, nthreads, cancel); });
    return ok;
}

template <class Op>
Image runNewImpl(const Image& src, OIIO::ROI roi, int nthreads, const Op& op) {
    const ImageView in = view(src);
    OIIO::ImageBuf out;
    if (!invoke(op, out, in.buf, roi, nthreads)) raiseError(out.geterror());
    return Image::fromBuf(std::move(out));
}

template <class Op>
bool runIntoImpl(Image& dst, const Image& src, OIIO::ROI roi, int nthreads, const Op& op) {
    ImageView in = view(src);
    ImageView out;
    const bool own = dst.writeable();
    OIIO::ImageBuf copy; // src, when it is dst's memory and the op would read what it wrote
    if (own) {
        out = view(dst);
        const size_t bytes = out.keep.nbytes(), srcBytes = in.keep.nbytes();
        const char *a = reinterpret_cast<const char*>(out.data),
                   *b = reinterpret_cast<const char*>(in.data);
        if (a < b + srcBytes && b < a + bytes) copy.copy(in.buf);
    }
    // A call Ctrl-C may stop works on a copy of dst's pixels, copied back once complete.
    const bool staged = own && std::is_same_v<Op, LongOp>;
    OIIO::ImageBuf stage;
    if (staged) stage.copy(out.buf);
    OIIO::ImageBuf& target = staged ? stage : out.buf;
    if (!invoke(op, target, copy.initialized() ? copy : in.buf, roi, nthreads)) {
        dst.error = target.geterror();
        return false;
    }
    if (staged && target.spec().image_bytes() == out.buf.spec().image_bytes() &&
        target.nchannels() == out.buf.nchannels() && target.localpixels()) {
        std::memcpy(const_cast<float*>(out.data), target.localpixels(),
                    size_t(target.spec().image_bytes()));
        dst.spec().extra_attribs = target.spec().extra_attribs;
    } else if (!own || target.localpixels() != out.data) {
        dst = Image::fromBuf(std::move(target));
    } else {
        // The pixels were written in place; the call may have added metadata.
        dst.spec().extra_attribs = out.buf.spec().extra_attribs;
    }
    return true;
}

} // namespace

Image runNew(const Image& src, OIIO::ROI roi, int nthreads, const ImageOp& op) {
    return runNewImpl(src, roi, nthreads, op);
}

Image runNew(const Image& src, OIIO::ROI roi, int nthreads, const LongOp& op) {
    return runNewImpl(src, roi, nthreads, op);
}

bool runInto(Image& dst, const Image& src, OIIO::ROI roi, int nthreads, const ImageOp& op) {
    return runIntoImpl(dst, src, roi, nthreads, op);
}

bool runInto(Image& dst, const Image& src, OIIO::ROI roi, int nthreads, const LongOp& op) {
    return runIntoImpl(dst, src, roi, nthreads, op);
}

} // namespace dhdr::python
