#include "py_ops.h"

namespace dhdr::python {

Image runNew(const Image& src, OIIO::ROI roi, int nthreads, const ImageOp& op) {
    const ImageView in = view(src);
    OIIO::ImageBuf out;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        ok = op(out, in.buf, roi, nthreads);
    }
    if (!ok) raiseError(out.geterror());
    return Image::fromBuf(std::move(out));
}

bool runInto(Image& dst, const Image& src, OIIO::ROI roi, int nthreads, const ImageOp& op) {
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
    bool ok = false;
    {
        py::gil_scoped_release gil;
        ok = op(out.buf, copy.initialized() ? copy : in.buf, roi, nthreads);
    }
    if (!ok) {
        dst.error = out.buf.geterror();
        return false;
    }
    if (!own || out.buf.localpixels() != out.data) {
        dst = Image::fromBuf(std::move(out.buf));
    } else {
        // The pixels were written in place; the call may have added metadata.
        dst.spec().extra_attribs = out.buf.spec().extra_attribs;
    }
    return true;
}

} // namespace dhdr::python
