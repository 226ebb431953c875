// Reading and writing through the tools' own readers and writer: colour found by name (layers,
// Blender's ViewLayer.Combined, Nuke's rgba, multi-part EXRs), outputs written atomically and
// never holding NaN or Inf.
#include "py_image.h"

#include <OpenImageIO/imageio.h>
#include <dhdr/io/errors.h>
#include <dhdr/io/image_output.h>
#include <dhdr/io/layers.h>
#include <pybind11/stl.h>

namespace dhdr::python {

namespace {

using namespace pybind11::literals;

Image readColour(const std::string& path, const std::string& layer, bool keepOthers, int nthreads) {
    OIIO::ImageBuf image;
    std::string error;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        ColourLayer chosen;
        size_t layers = 0;
        std::vector<OIIO::TypeDesc> formats;
        ok = findColourLayer(path, layer, chosen, layers, error);
        if (ok && !readColourLayer(path, chosen, keepOthers, nthreads, image, formats, error)) {
            error = cannotRead(path, error);
            ok = false;
        }
    }
    if (!ok) raiseError(error);
    return Image::fromBuf(std::move(image));
}

OIIO::TypeDesc pixelType(const std::string& type) {
    if (type == "half") return OIIO::TypeDesc::HALF;
    if (type == "float") return OIIO::TypeDesc::FLOAT;
    if (type == "uint8") return OIIO::TypeDesc::UINT8;
    if (type == "uint16") return OIIO::TypeDesc::UINT16;
    throw py::value_error("type must be half, float, uint8 or uint16, got '" + type + "'");
}

// Writes `buf` (any pixel type) to `path` as `type`; warnings (values made finite or
// clamped) go to Python's warnings.
void writeImage(const std::string& path, const OIIO::ImageBuf& buf, OIIO::TypeDesc type,
                const std::string& compression) {
    ImageOutputOptions options;
    options.software = "dhdr python module (dhdr " DHDR_VERSION ")";
    options.compression = compression;
    std::vector<std::string> warnings;
    std::string error;
    {
        py::gil_scoped_release gil;
        ImageFileOutput file(path, options);
        if (file.open(buf.spec(), {type}) && file.writeRows(buf, buf.roi()) && file.commit())
            warnings = file.warnings();
        else
            error = file.geterror();
    }
    if (!error.empty()) raiseError(error);
    for (const std::string& w : warnings)
        warn(w);
}

} // namespace

void bindImageIO(py::module_& m) {
    m.def("read", &readColour, "path"_a, py::kw_only(), "layer"_a = "", "keep_others"_a = true,
          "nthreads"_a = 0,
          R"(Reads the colour of an image file as the tools do (their --layer): the layer or EXR
part named layer (a full name, a part, a channel prefix or its last component), else the
unnamed R, G, B, A, else the one Blender (Combined), Nuke (rgba) or renderers (beauty)
name. Channels 0-2 (3) are then R, G, B (A); with keep_others the part's other channels
follow. Errors are the tools' messages ("PATH: no such file", a list of the layers, ...).)");
    m.def(
        "layers",
        [](const std::string& path) {
            std::vector<ColourLayer> layers;
            std::string error;
            if (!listColourLayers(path, layers, error)) raiseError(cannotRead(path, error));
            std::vector<std::string> names;
            for (const ColourLayer& l : layers)
                names.push_back(l.name());
            return names;
        },
        "path"_a, "The colour layers of a file, by the names read(layer=...) takes.");
    m.def(
        "write",
        [](const std::string& path, const py::object& image, const std::string& type,
           const std::string& compression) {
            checkImageName(path, "path");
            // Integers (quantize's arrays) as they are: PNG, TIFF.
            if (py::isinstance<py::array_t<uint8_t>>(image) ||
                py::isinstance<py::array_t<uint16_t>>(image)) {
                auto a = py::array::ensure(image);
                const bool eight = py::isinstance<py::array_t<uint8_t>>(image);
                if (a.ndim() != 3 || !(a.flags() & py::array::c_style))
                    throw py::value_error("image: expected a C-contiguous (height, width, "
                                          "channels) array");
                const OIIO::TypeDesc t = eight ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16;
                OIIO::ImageSpec spec(int(a.shape(1)), int(a.shape(0)), int(a.shape(2)), t);
                const OIIO::ImageBuf buf(spec, const_cast<void*>(a.data()));
                writeImage(path, buf, type.empty() ? t : pixelType(type), compression);
                return;
            }
            Image storage;
            const ImageView v = view(asImage(image, "image", storage));
            writeImage(path, v.buf, type.empty() ? OIIO::TypeDesc::HALF : pixelType(type),
                       compression);
        },
        "path"_a, "image"_a, py::kw_only(), "type"_a = "", "compression"_a = "",
        R"(Writes an Image (or a float array) as the tools write: under a temporary name renamed
into place when complete, NaN as 0 and Inf as the type's largest value (a RuntimeWarning
says how many). type: half (default for float pixels), float, uint8, uint16; a uint8 or
uint16 array (quantize's) is written as it is. compression: OpenImageIO's names.)");
}

} // namespace dhdr::python
