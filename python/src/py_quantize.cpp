// quantize: display values to the integers PNG and TIFF get (libtonemap's quantize, as
// dhdr-tonemap writes them).
#include "py_ops.h"

#include <dhdr/tonemap/quantize.h>

namespace dhdr::python {

namespace {

using namespace pybind11::literals;

// Quantized pixels: an integer array of src's size and channels (bits from its dtype).
bool quantizeInto(py::array& dst, const Image& src, bool dither, OIIO::ROI roi, int nthreads) {
    const OIIO::TypeDesc type = py::isinstance<py::array_t<uint8_t>>(dst) ? OIIO::TypeDesc::UINT8
                                : py::isinstance<py::array_t<uint16_t>>(dst)
                                    ? OIIO::TypeDesc::UINT16
                                    : OIIO::TypeDesc::UNKNOWN;
    if (type == OIIO::TypeDesc::UNKNOWN || dst.ndim() != 3 || !dst.writeable() ||
        !(dst.flags() & py::array::c_style))
        throw py::type_error("dst: expected a writable C-contiguous uint8 or uint16 array of "
                             "shape (height, width, channels)");
    const OIIO::ImageSpec& s = src.spec();
    if (dst.shape(0) != s.height || dst.shape(1) != s.width || dst.shape(2) != s.nchannels)
        throw py::value_error("dst: shape (" + std::to_string(dst.shape(0)) + ", " +
                              std::to_string(dst.shape(1)) + ", " + std::to_string(dst.shape(2)) +
                              ") is not src's (" + std::to_string(s.height) + ", " +
                              std::to_string(s.width) + ", " + std::to_string(s.nchannels) + ")");
    Image finite;
    const ImageView in = view(finiteImage(src, "src", finite));
    OIIO::ImageSpec spec(int(dst.shape(1)), int(dst.shape(0)), int(dst.shape(2)), type);
    spec.x = in.buf.spec().x;
    spec.y = in.buf.spec().y;
    OIIO::ImageBuf out(spec, dst.mutable_data());
    QuantizeParams p;
    p.dither = dither;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        ok = quantize(out, in.buf, p, roi, nthreads);
    }
    if (!ok) raiseError(out.geterror());
    return true;
}

} // namespace

void bindQuantize(py::module_& m) {
    m.def(
        "quantize",
        [](py::array dst, const py::object& src, bool dither, const py::object& roi, int nthreads) {
            Image storage;
            return quantizeInto(dst, asImage(src, "src", storage), dither, toRoi(roi), nthreads);
        },
        "dst"_a, "src"_a, py::kw_only(), "dither"_a = true, "roi"_a = py::none(), "nthreads"_a = 0);
    m.def(
        "quantize",
        [](const py::object& src, int bits, bool dither, const py::object& roi, int nthreads) {
            Image storage;
            const Image& image = asImage(src, "src", storage);
            if (bits != 8 && bits != 16)
                throw py::value_error("bits: " + std::to_string(bits) + " is not 8 or 16");
            const std::vector<py::ssize_t> shape = {image.spec().height, image.spec().width,
                                                    image.spec().nchannels};
            py::array dst = bits == 8 ? py::array(py::array_t<uint8_t>(shape))
                                      : py::array(py::array_t<uint16_t>(shape));
            quantizeInto(dst, image, dither, toRoi(roi), nthreads);
            return dst;
        },
        "src"_a, py::kw_only(), "bits"_a = 8, "dither"_a = true, "roi"_a = py::none(),
        "nthreads"_a = 0,
        R"(Display values to integers (dhdr-tonemap's PNG/TIFF output): round(clamp(v, 0, 1) x
(2^bits - 1) + offset), the offset from an 8x8 Bayer matrix on R, G, B when dither (the tool
dithers 8-bit output unless --no-dither, never 16-bit). Returns a uint8 or uint16 array
(height, width, channels); the dst form fills such an array.)");
}

} // namespace dhdr::python
