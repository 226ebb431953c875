#include "py_deep.h"

#include <OpenImageIO/deepdata.h>
#include <algorithm>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/io/image_output.h>
#include <dhdr/io/pixel_limit.h>
#include <pybind11/stl.h>

namespace dhdr::python {

using namespace pybind11::literals;

std::vector<OIIO::TypeDesc> deepFileFormats(const OIIO::ImageSpec& spec) {
    if (!gbuffer::isWrittenLayout(spec.channelnames, true))
        throw py::value_error("gbuffer: not the channels of a deep dhdr G-buffer, in order "
                              "(render_gbuffer(deep=True)'s)");
    return gbuffer::channelFormats(spec.channelnames);
}

bool readDeep(const std::string& path, int part, DeepGBuffer& out, std::string& error) {
    if (readDeepGBuffer(path, part, out, error)) return true;
    error = path + ": " + error;
    return false;
}

namespace {

// The base of every array over a DeepGBuffer: it keeps the samples alive after the Python
// object is gone.
py::capsule keeper(const std::shared_ptr<DeepGBuffer>& g) {
    return py::capsule(new std::shared_ptr<DeepGBuffer>(g),
                       [](void* p) { delete static_cast<std::shared_ptr<DeepGBuffer>*>(p); });
}

py::array_t<float> samplesOf(const DeepHandle& d) {
    const DeepGBuffer& g = *d.g;
    const py::ssize_t n = py::ssize_t(g.totalSamples()), c = g.spec.nchannels;
    if (n == 0) return py::array_t<float>({n, c});
    return py::array_t<float>({n, c}, g.values.data(), keeper(d.g));
}

int channelIndex(const DeepHandle& d, const std::string& name) {
    const std::vector<std::string>& names = d.g->spec.channelnames;
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) throw py::key_error("no channel '" + name + "' in the deep G-buffer");
    return int(it - names.begin());
}

// One channel of every sample: a strided view of the samples.
py::array_t<float> channelOf(const DeepHandle& d, const std::string& name) {
    const DeepGBuffer& g = *d.g;
    const int c = channelIndex(d, name);
    const py::ssize_t n = py::ssize_t(g.totalSamples());
    const py::ssize_t stride = py::ssize_t(sizeof(float)) * g.spec.nchannels;
    if (n == 0) return py::array_t<float>({n});
    return py::array_t<float>({n}, {stride}, g.values.data() + c, keeper(d.g));
}

py::array_t<std::uint32_t> countsOf(const DeepHandle& d) {
    const DeepGBuffer& g = *d.g;
    py::array_t<std::uint32_t> out({g.spec.height, g.spec.width});
    std::uint32_t* p = out.mutable_data();
    for (size_t i = 0, n = size_t(g.spec.width) * size_t(g.spec.height); i < n; ++i)
        p[i] = g.first[i + 1] - g.first[i];
    return out;
}

// A DeepGBuffer from Python's pieces: per-pixel counts and the (samples, channels) array.
DeepHandle fromArrays(const py::object& countsGiven, const py::object& samplesGiven,
                      const std::vector<std::string>& channels, const py::object& attributes) {
    auto counts =
        py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(countsGiven);
    if (!counts || counts.ndim() != 2)
        throw py::value_error("counts: expected an array of shape (height, width)");
    auto samples =
        py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(samplesGiven);
    const std::vector<std::string> names =
        channels.empty() ? gbuffer::deepChannelNames() : channels;
    if (!samples || samples.ndim() != 2 || size_t(samples.shape(1)) != names.size())
        throw py::value_error("samples: expected an array of shape (samples, " +
                              std::to_string(names.size()) + ") (one column a channel)");
    const int width = int(counts.shape(1)), height = int(counts.shape(0));
    if (width <= 0 || height <= 0) throw py::value_error("counts: the image is empty");
    if (const std::string e = pixelLimitError(width, height); !e.empty())
        throw py::value_error("counts: " + e);
    DeepHandle d;
    DeepGBuffer& g = *d.g;
    g.spec = OIIO::ImageSpec(width, height, int(names.size()), OIIO::TypeDesc::FLOAT);
    g.spec.channelnames = names;
    g.first.assign(size_t(width) * size_t(height) + 1, 0);
    const long long* c = counts.data();
    unsigned long long total = 0;
    for (size_t i = 0, n = g.first.size() - 1; i < n; ++i) {
        if (c[i] < 0) throw py::value_error("counts: a negative count");
        total += (unsigned long long)c[i];
        if (total > 0xffffffffull) throw py::value_error("counts: more than 2^32 samples");
        g.first[i + 1] = std::uint32_t(total);
    }
    if (total != (unsigned long long)samples.shape(0))
        throw py::value_error("samples: " + std::to_string(samples.shape(0)) +
                              " rows, but the counts add up to " + std::to_string(total));
    g.values.assign(samples.data(), samples.data() + samples.size());
    if (!attributes.is_none())
        for (const auto& [name, value] : attributes.cast<py::dict>())
            setAttribute(g.spec, py::str(name), value);
    return d;
}

} // namespace

void bindDeep(py::module_& m) {
    py::class_<DeepHandle>(m, "DeepGBuffer", R"(A deep G-buffer (docs/gbuffer.md): per pixel every
surface up to the first opaque one, front to back, each sample with the contract's channels,
as OpenImageIO's DeepData holds it: counts[y, x] samples a pixel, and samples, one row a
sample (pixels in scanline order, each pixel's samples front to back) and one column a
channel. g["albedo.R"] is that channel of every sample (a view); g.pixel(x, y) a pixel's
samples; offsets[i] the row of pixel i's first sample. The arrays are views of the G-buffer's
own memory: editing samples changes what light() shades.
DeepGBuffer(counts, samples, channels=[], attributes=None) builds one (channels: the deep
contract's by default; attributes: the header, e.g. worldToCamera and worldToNDC).)")
        .def(py::init(&fromArrays), "counts"_a, "samples"_a,
             "channels"_a = std::vector<std::string>{}, "attributes"_a = py::none())
        .def_property_readonly("width", [](const DeepHandle& d) { return d.g->spec.width; })
        .def_property_readonly("height", [](const DeepHandle& d) { return d.g->spec.height; })
        .def_property_readonly(
            "origin", [](const DeepHandle& d) { return py::make_tuple(d.g->spec.x, d.g->spec.y); })
        .def_property_readonly("channels",
                               [](const DeepHandle& d) { return d.g->spec.channelnames; })
        .def_property_readonly("attributes",
                               [](const DeepHandle& d) { return attributesOf(d.g->spec); })
        .def_property_readonly("total_samples",
                               [](const DeepHandle& d) { return d.g->totalSamples(); })
        .def_property_readonly("counts", &countsOf,
                               "Samples per pixel, (height, width) uint32 (a new array).")
        .def_property_readonly(
            "offsets",
            [](const DeepHandle& d) {
                py::array_t<std::uint32_t> a({py::ssize_t(d.g->first.size())}, d.g->first.data(),
                                             keeper(d.g));
                a.attr("setflags")("write"_a = false);
                return a;
            },
            "Each pixel's first row in samples, and the total at the end: width * height + 1 "
            "uint32 (read-only).")
        .def_property_readonly("samples", &samplesOf,
                               "Every sample, (total_samples, channels) float32, a writable view.")
        .def("__getitem__", &channelOf, "name"_a)
        .def("channel", &channelOf, "name"_a,
             "One channel of every sample, (total_samples,) float32, a writable view.")
        .def(
            "pixel",
            [](const DeepHandle& d, int x, int y) {
                const OIIO::ImageSpec& s = d.g->spec;
                if (x < s.x || y < s.y || x >= s.x + s.width || y >= s.y + s.height)
                    throw py::index_error("pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                          ") is outside the image");
                const size_t first = d.g->first[d.g->pixel(x, y)];
                return py::array_t<float>(
                    {py::ssize_t(d.g->samples(x, y)), py::ssize_t(s.nchannels)},
                    d.g->values.data() + first * size_t(s.nchannels), keeper(d.g));
            },
            "x"_a, "y"_a, "The samples of pixel (x, y), front to back: (n, channels), a view.")
        .def("__repr__", [](const DeepHandle& d) {
            return "dhdr.DeepGBuffer(" + std::to_string(d.g->spec.width) + "x" +
                   std::to_string(d.g->spec.height) + ", " + std::to_string(d.g->totalSamples()) +
                   " samples)";
        });

    m.def(
        "write_gbuffer",
        [](const std::string& path, const DeepHandle& d) {
            checkImageName(path, "path");
            const std::vector<OIIO::TypeDesc> formats = deepFileFormats(d.g->spec);
            const std::shared_ptr<const DeepGBuffer> g = d.g;
            std::string error;
            {
                py::gil_scoped_release gil;
                ImageOutputOptions options;
                options.software = "dhdr python module (dhdr " DHDR_VERSION ")";
                ImageFileOutput file(path, options);
                OIIO::ImageSpec spec = g->spec;
                spec.channelformats = formats;
                bool ok = file.openDeep(spec);
                // dhdr-gbuffer's strips of 64 rows: memory for one strip's DeepData at a time.
                for (int y = spec.y; ok && y < spec.y + spec.height; y += 64) {
                    const int yend = std::min(y + 64, spec.y + spec.height);
                    OIIO::DeepData data;
                    toDeepData(*g, y, yend, data, formats);
                    ok = file.writeDeepRows(y, yend, data);
                }
                if (!ok || !file.commit()) error = file.geterror();
            }
            if (!error.empty()) raiseError(error);
        },
        "path"_a, "gbuffer"_a,
        "A DeepGBuffer as dhdr-gbuffer --deep writes it: a deep scanline EXR, each channel in the "
        "contract's type, atomically.");
}

} // namespace dhdr::python
