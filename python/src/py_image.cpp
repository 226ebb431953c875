#include "py_image.h"

#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <dhdr/io/motion_channels.h>
#include <dhdr/io/sanitize.h>
#include <limits>
#include <pybind11/stl.h>
#include <stdexcept>

namespace dhdr::python {

namespace {

std::string typeName(const py::handle& object) {
    return py::str(py::type::handle_of(object).attr("__name__"));
}

std::string shapeText(const py::array& a) {
    std::string text = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i)
        text += (i ? ", " : "") + std::to_string(a.shape(i));
    return text + (a.ndim() == 1 ? ",)" : ")");
}

// The array `object` is, as C-contiguous float32 (height, width, channels); numpy copies only
// when the dtype or the layout differ.
py::array_t<float> floatPixels(const py::handle& object, const char* what) {
    py::array a = py::array::ensure(object);
    const char kind = a ? a.dtype().kind() : 'O';
    if (!a || (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b'))
        throw py::type_error(std::string(what) +
                             ": expected a dhdr.Image or a numeric array of shape (height, "
                             "width[, channels]), got " +
                             typeName(object) +
                             (a ? " of dtype " + std::string(py::str(a.dtype())) : ""));
    if (a.ndim() != 2 && a.ndim() != 3)
        throw py::value_error(std::string(what) +
                              ": expected an array of shape (height, width) or (height, width, "
                              "channels), got shape " +
                              shapeText(a));
    if (a.size() == 0)
        throw py::value_error(std::string(what) + ": the array has no pixels (shape " +
                              shapeText(a) + ")");
    // A conversion that fails (a broadcast view of more bytes than memory holds) raises
    // numpy's error, named after the argument; ensure() would clear it.
    py::array_t<float, py::array::c_style | py::array::forcecast> f;
    try {
        f = py::array_t<float, py::array::c_style | py::array::forcecast>(a);
    } catch (py::error_already_set& e) {
        const std::string text = std::string(what) + ": cannot make the array of shape " +
                                 shapeText(a) + " C-contiguous float32: " + e.what();
        if (e.matches(PyExc_MemoryError)) {
            PyErr_SetString(PyExc_MemoryError, text.c_str());
            throw py::error_already_set();
        }
        throw py::value_error(text);
    }
    for (py::ssize_t i = 0; i < f.ndim(); ++i)
        if (f.shape(i) > std::numeric_limits<int>::max())
            throw py::value_error(std::string(what) + ": shape " + shapeText(a) +
                                  " is larger than an image can be");
    if (f.ndim() == 2) return f.reshape({f.shape(0), f.shape(1), py::ssize_t(1)});
    return f;
}

// A float spec of `pixels`' size with `names` (or OpenImageIO's defaults), keeping `like`'s
// metadata.
OIIO::ImageSpec specFor(const py::array_t<float>& pixels, const std::vector<std::string>& names,
                        const OIIO::ImageSpec* like, const char* what) {
    const int h = int(pixels.shape(0)), w = int(pixels.shape(1)), c = int(pixels.shape(2));
    OIIO::ImageSpec spec = like ? *like : OIIO::ImageSpec(w, h, c, OIIO::TypeDesc::FLOAT);
    spec.width = spec.full_width = w;
    spec.height = spec.full_height = h;
    spec.full_x = spec.x;
    spec.full_y = spec.y;
    spec.depth = spec.full_depth = 1;
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.channelformats.clear();
    if (!names.empty() && int(names.size()) != c)
        throw py::value_error(std::string(what) + ": " + std::to_string(names.size()) +
                              " channel names for " + std::to_string(c) + " channels");
    if (!names.empty()) {
        spec.channelnames = names;
    } else if (spec.nchannels != c || int(spec.channelnames.size()) != c) {
        spec.nchannels = c;
        spec.default_channel_names();
    }
    spec.nchannels = c;
    const auto index = [&](const char* n) {
        const auto it = std::find(spec.channelnames.begin(), spec.channelnames.end(), n);
        return it == spec.channelnames.end() ? -1 : int(it - spec.channelnames.begin());
    };
    spec.alpha_channel = index("A");
    spec.z_channel = index("Z");
    return spec;
}

py::object attributeValue(const OIIO::ParamValue& p) {
    const OIIO::TypeDesc t = p.type();
    if (t == OIIO::TypeMatrix44) {
        const float* m = static_cast<const float*>(p.data());
        py::list rows;
        for (int r = 0; r < 4; ++r)
            rows.append(py::make_tuple(m[4 * r], m[4 * r + 1], m[4 * r + 2], m[4 * r + 3]));
        return rows;
    }
    const int n = p.nvalues() * int(t.aggregate) * std::max(int(t.arraylen), 1);
    auto one = [&](int i) -> py::object {
        switch (t.basetype) {
        case OIIO::TypeDesc::STRING:
            return py::str(static_cast<const OIIO::ustring*>(p.data())[i].string());
        case OIIO::TypeDesc::INT:
            return py::int_(static_cast<const int*>(p.data())[i]);
        case OIIO::TypeDesc::UINT:
            return py::int_(static_cast<const unsigned*>(p.data())[i]);
        case OIIO::TypeDesc::FLOAT:
            return py::float_(static_cast<const float*>(p.data())[i]);
        case OIIO::TypeDesc::DOUBLE:
            return py::float_(static_cast<const double*>(p.data())[i]);
        default:
            return py::str(p.get_string());
        }
    };
    const auto b = OIIO::TypeDesc::BASETYPE(t.basetype);
    const bool known = b == OIIO::TypeDesc::STRING || b == OIIO::TypeDesc::INT ||
                       b == OIIO::TypeDesc::UINT || b == OIIO::TypeDesc::FLOAT ||
                       b == OIIO::TypeDesc::DOUBLE;
    // Other types (half, 8- and 16-bit integers, pointers) as OpenImageIO prints them.
    if (!known) return py::str(p.get_string());
    if (n == 1) return one(0);
    py::list values;
    for (int i = 0; i < n; ++i)
        values.append(one(i));
    return values;
}

} // namespace

Image::Image(const py::object& pixels, const std::vector<std::string>& channels, const char* what)
    : m_pixels(floatPixels(pixels, what)), m_spec(specFor(m_pixels, channels, nullptr, what)) {}

Image Image::fromBuf(OIIO::ImageBuf&& buf) {
    Image image;
    const OIIO::ImageSpec& s = buf.spec();
    const std::vector<py::ssize_t> shape = {s.height, s.width, s.nchannels};
    if (s.format == OIIO::TypeDesc::FLOAT && s.depth == 1 && buf.localpixels() &&
        buf.storage() == OIIO::ImageBuf::LOCALBUFFER) {
        // The ImageBuf, moved to the heap, is the array's memory from now on; its destructor
        // runs when the last view of the array goes.
        auto* owner = new OIIO::ImageBuf(std::move(buf));
        py::capsule base(owner, [](void* p) { delete static_cast<OIIO::ImageBuf*>(p); });
        image.m_pixels =
            py::array_t<float>(shape, static_cast<const float*>(owner->localpixels()), base);
        image.m_spec = owner->spec();
    } else {
        image.m_pixels = py::array_t<float>(shape);
        buf.get_pixels(buf.roi(), OIIO::TypeDesc::FLOAT, image.m_pixels.mutable_data());
        image.m_spec = s;
    }
    image.m_spec = specFor(image.m_pixels, image.m_spec.channelnames, &image.m_spec, "result");
    return image;
}

void Image::setPixels(const py::object& pixels) {
    py::array_t<float> p = floatPixels(pixels, "pixels");
    const bool same = m_pixels && p.shape(2) == m_pixels.shape(2);
    m_spec = specFor(p, same ? m_spec.channelnames : std::vector<std::string>{},
                     m_pixels ? &m_spec : nullptr, "pixels");
    m_pixels = std::move(p);
}

void Image::setChannels(const std::vector<std::string>& names) {
    if (!m_pixels) throw py::value_error("channels: the image has no pixels");
    m_spec = specFor(m_pixels, names, &m_spec, "channels");
}

ImageView view(const Image& image) {
    if (image.empty()) throw py::value_error("the image is empty (it has no pixels)");
    ImageView v;
    v.keep = image.pixels();
    v.data = v.keep.data();
    v.buf = OIIO::ImageBuf(image.spec(), const_cast<float*>(v.data));
    return v;
}

const Image& asImage(const py::handle& object, const char* what, Image& storage) {
    if (py::isinstance<Image>(object)) {
        const Image& image = object.cast<const Image&>();
        if (image.empty())
            throw py::value_error(std::string(what) + ": the image is empty (it has no pixels)");
        return image;
    }
    // An OpenImageIO.ImageBuf, as dhdr.from_imagebuf converts it (names and origin kept).
    const py::handle type = py::type::handle_of(object);
    if (py::str(type.attr("__name__")).cast<std::string>() == "ImageBuf" &&
        py::str(type.attr("__module__")).cast<std::string>() == "OpenImageIO") {
        storage = py::module_::import("dhdr").attr("from_imagebuf")(object).cast<Image>();
        return storage;
    }
    storage = Image(py::reinterpret_borrow<py::object>(object), {}, what);
    return storage;
}

namespace {

// Whether any of `n` floats is NaN or ±Inf (all exponent bits set); a loop the compiler
// vectorizes, so that finite images, the usual case, cost one read.
bool anyNonFinite(const float* p, size_t n) {
    unsigned bad = 0;
    for (size_t i = 0; i < n; ++i) {
        uint32_t u;
        std::memcpy(&u, p + i, sizeof u);
        bad |= unsigned((u & 0x7f800000u) == 0x7f800000u);
    }
    return bad != 0;
}

} // namespace

const Image& finiteImage(const Image& image, const char* what, Image& storage) {
    const py::array_t<float>& pixels = image.pixels();
    bool bad = false;
    {
        py::gil_scoped_release gil;
        bad = anyNonFinite(pixels.data(), size_t(pixels.size()));
    }
    if (!bad) return image;
    // The depth's +Inf means no surface (the G-buffer contract): it stays.
    const int depth = findMotionChannels(image.spec()).depth;
    Image copy = image;
    copy.setPixels(image.pixels().attr("copy")());
    ImageView v = view(copy);
    NonFiniteCount n;
    {
        py::gil_scoped_release gil;
        for (int c = 0; c < v.buf.nchannels(); ++c) {
            if (c == depth || v.buf.spec().channelnames[size_t(c)] == "ZBack") continue;
            OIIO::ROI r = v.buf.roi();
            r.chbegin = c;
            r.chend = c + 1;
            n += replaceNonFinite(v.buf, r, 1);
        }
    }
    storage = std::move(copy);
    if (n.total() > 0)
        warn(std::string(what) + ": " + std::to_string(n.nan) + " NaN, " +
             std::to_string(n.positiveInf) + " +Inf and " + std::to_string(n.negativeInf) +
             " -Inf values read as 0, " + std::to_string(int(kInfinityReplacement)) +
             " and 0, as the tools read them");
    return storage;
}

OIIO::ROI toRoi(const py::handle& roi) {
    if (roi.is_none()) return OIIO::ROI::All();
    std::vector<int> v;
    if (py::isinstance<py::tuple>(roi) || py::isinstance<py::list>(roi)) {
        for (const py::handle& x : roi)
            v.push_back(x.cast<int>());
        if (v.size() != 4 && v.size() != 6)
            throw py::value_error("roi: expected (xbegin, xend, ybegin, yend[, chbegin, chend]), "
                                  "got " +
                                  std::to_string(v.size()) + " numbers");
    } else if (py::hasattr(roi, "xbegin")) {
        for (const char* a : {"xbegin", "xend", "ybegin", "yend", "chbegin", "chend"})
            v.push_back(roi.attr(a).cast<int>());
    } else {
        throw py::type_error("roi: expected None, a tuple (xbegin, xend, ybegin, yend[, chbegin, "
                             "chend]) or an OpenImageIO.ROI, got " +
                             typeName(roi));
    }
    OIIO::ROI r(v[0], v[1], v[2], v[3], 0, 1, v.size() == 6 ? v[4] : 0,
                v.size() == 6 ? v[5] : 10000);
    if (r.defined() && (r.width() <= 0 || r.height() <= 0 || r.nchannels() <= 0))
        throw py::value_error("roi: the region is empty");
    return r;
}

py::dict attributesOf(const OIIO::ImageSpec& spec) {
    py::dict d;
    for (const OIIO::ParamValue& p : spec.extra_attribs)
        d[py::str(p.name().string())] = attributeValue(p);
    return d;
}

void setAttribute(OIIO::ImageSpec& spec, const std::string& name, const py::handle& value) {
    if (py::isinstance<py::str>(value)) {
        spec.attribute(name, value.cast<std::string>());
    } else if (py::isinstance<py::bool_>(value) || py::isinstance<py::int_>(value)) {
        spec.attribute(name, value.cast<int>());
    } else if (py::isinstance<py::float_>(value)) {
        spec.attribute(name, value.cast<float>());
    } else if ((py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) &&
               py::len(value) > 0 && py::isinstance<py::str>(value[py::int_(0)])) {
        // A list of strings: a name table (dhdr:objectNames, dhdr:materialNames).
        const std::vector<std::string> names = value.cast<std::vector<std::string>>();
        std::vector<const char*> pointers;
        for (const std::string& n : names)
            pointers.push_back(n.c_str());
        spec.attribute(name, OIIO::TypeDesc(OIIO::TypeDesc::STRING, int(pointers.size())),
                       pointers.data());
    } else {
        // A 4x4 matrix, nested or flat (worldToCamera, worldToNDC), a 3-vector
        // (dhdr:cameraPosition) or float numbers: what attributes gives back sets again.
        py::array_t<float, py::array::c_style | py::array::forcecast> m =
            py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
        if (!m || m.size() == 0 || (m.ndim() != 1 && m.size() != 16))
            throw py::type_error("set_attribute: " + name +
                                 ": expected a str, int, float, numbers or 4x4 matrix, got " +
                                 typeName(value));
        const OIIO::TypeDesc type = m.size() == 16 ? OIIO::TypeMatrix44
                                    : m.size() == 3
                                        ? OIIO::TypeVector
                                        : OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, int(m.size()));
        spec.attribute(name, type, m.data());
    }
}

void warn(const std::string& message) {
    if (PyErr_WarnEx(PyExc_RuntimeWarning, message.c_str(), 1) < 0) throw py::error_already_set();
}

void checkImageName(const std::string& path, const char* what) {
    if (path.find('?') != std::string::npos)
        throw py::value_error(std::string(what) + ": " + path +
                              ": an image whose name holds '?' cannot be read back (OpenImageIO "
                              "takes what follows '?' for options: file.exr?key=value); choose a "
                              "name without '?'");
}

void raiseError(const std::string& message) {
    throw std::runtime_error(message.empty() ? "unknown error" : message);
}

void bindImage(py::module_& m) {
    using namespace pybind11::literals;
    py::class_<Image>(m, "Image",
                      R"(An image in memory: float32 pixels of shape (height, width, channels)
in a numpy array, with channel names, an origin and the file's metadata.

Image(pixels, channels=[]) takes any numeric array of shape (height, width) or
(height, width, channels); a float32 C-contiguous one is used without a copy, others are
converted. Image() is empty: a destination for op(dst, src, ...) forms.)")
        .def(py::init<>())
        .def(py::init([](const py::object& pixels, const std::vector<std::string>& channels) {
                 return Image(pixels, channels);
             }),
             "pixels"_a, "channels"_a = std::vector<std::string>{})
        .def_property(
            "pixels",
            [](const Image& i) -> py::object {
                if (i.empty()) return py::none();
                return i.pixels();
            },
            [](Image& i, const py::object& p) { i.setPixels(p); },
            "The pixels, float32 (height, width, channels); writing to the array changes the "
            "image.")
        .def_property(
            "channels", [](const Image& i) { return i.spec().channelnames; },
            [](Image& i, const std::vector<std::string>& n) { i.setChannels(n); })
        .def_property_readonly("width",
                               [](const Image& i) { return i.empty() ? 0 : i.spec().width; })
        .def_property_readonly("height",
                               [](const Image& i) { return i.empty() ? 0 : i.spec().height; })
        .def_property_readonly("nchannels",
                               [](const Image& i) { return i.empty() ? 0 : i.spec().nchannels; })
        .def_property_readonly("empty", &Image::empty)
        .def_property(
            "origin", [](const Image& i) { return py::make_tuple(i.spec().x, i.spec().y); },
            [](Image& i, std::pair<int, int> xy) {
                i.spec().x = i.spec().full_x = xy.first;
                i.spec().y = i.spec().full_y = xy.second;
            },
            "Pixel coordinates of the top-left pixel (the EXR data window's origin).")
        .def_property_readonly(
            "attributes", [](const Image& i) { return attributesOf(i.spec()); },
            "The metadata (EXR header attributes) as a dict; matrices as 4x4 lists.")
        .def(
            "set_attribute",
            [](Image& i, const std::string& name, const py::object& value) {
                setAttribute(i.spec(), name, value);
            },
            "name"_a, "value"_a,
            "Sets a header attribute: a str, int, float, numbers (3: a vector), a 4x4 matrix or "
            "a list of str (a name table), as attributes gives them.")
        .def(
            "channel",
            [](const Image& i, const std::string& name) -> py::object {
                const auto& names = i.spec().channelnames;
                const auto it = std::find(names.begin(), names.end(), name);
                if (i.empty() || it == names.end()) {
                    std::string list;
                    for (const std::string& n : names)
                        list += (list.empty() ? "" : ", ") + n;
                    throw py::key_error("no channel '" + name + "' (channels: " + list + ")");
                }
                return i.pixels()[py::make_tuple(py::ellipsis(), int(it - names.begin()))];
            },
            "name"_a, "A view of one channel, (height, width), by name.")
        .def("__getitem__", [](const py::object& self,
                               const std::string& name) { return self.attr("channel")(name); })
        .def("copy",
             [](const Image& i) {
                 Image c = i;
                 if (!i.empty()) c.setPixels(i.pixels().attr("copy")());
                 return c;
             })
        .def(
            "__array__",
            [](const Image& i, const py::object& dtype) -> py::object {
                if (i.empty()) throw py::value_error("the image is empty (it has no pixels)");
                if (dtype.is_none()) return i.pixels();
                return i.pixels().attr("astype")(dtype);
            },
            "dtype"_a = py::none())
        .def("geterror", [](Image& i) { return std::exchange(i.error, {}); })
        .def("has_error", [](const Image& i) { return !i.error.empty(); })
        .def("__repr__", [](const Image& i) {
            if (i.empty()) return std::string("dhdr.Image()");
            std::string names;
            for (const std::string& n : i.spec().channelnames)
                names += (names.empty() ? "" : ", ") + n;
            return "dhdr.Image(" + std::to_string(i.spec().width) + "x" +
                   std::to_string(i.spec().height) + ", channels " + names + ")";
        });
}

} // namespace dhdr::python
