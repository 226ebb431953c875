// Reading what the lighting stage lights (libdeferred, libio): dhdr G-buffers as dhdr-light
// reads them, another renderer's passes through a channel map, and lights files as dicts.
#include "py_deep.h"
#include "py_lights.h"

#include <OpenImageIO/imageio.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_import.h>
#include <dhdr/deferred/scene/lights.h>
#include <dhdr/io/errors.h>
#include <dhdr/io/pixel_limit.h>
#include <dhdr/io/sanitize.h>
#include <dhdr/io/strip_reader.h>
#include <pybind11/stl.h>

namespace dhdr::python {

namespace {

using namespace pybind11::literals;

// A dhdr G-buffer whole, as dhdr-light reads it: a flat one strip by strip, its part found by
// the contract, every channel as float, NaN and ±Inf replaced except in Z (whose background is
// +Inf by contract); a deep one into `deep` (deep.h). Called without the GIL; false with the
// tool's message.
bool readGBuffer(const std::string& path, int nthreads, OIIO::ImageBuf& gbuf, DeepHandle& deep,
                 bool& isDeep, std::string& error) {
    int part = 0;
    if (!gbuffer::probeGBufferFile(path, part, isDeep, error)) return false;
    if (isDeep) return readDeep(path, part, *deep.g, error);
    StripReader reader;
    if (!reader.open(path, part, 0, 1 << 20, nthreads, error)) {
        error = cannotRead(path, error);
        return false;
    }
    const OIIO::ImageSpec& spec = reader.spec();
    gbuffer::Layout layout;
    std::string missing;
    if (!gbuffer::findLayout(spec, layout, missing)) {
        error = path + ": no channel '" + missing + "' — is this a G-buffer?";
        return false;
    }
    if (!reader.read(spec.y, spec.y + spec.height, gbuf, error)) {
        error = cannotRead(path, error);
        return false;
    }
    OIIO::ROI before = gbuf.roi(), after = gbuf.roi();
    before.chend = layout.depth;
    after.chbegin = layout.depth + 1;
    replaceNonFinite(gbuf, before, nthreads);
    if (after.chbegin < after.chend) replaceNonFinite(gbuf, after, nthreads);
    return true;
}

} // namespace

void bindGBufferInput(py::module_& m) {
    m.def(
        "read_gbuffer",
        [](const std::string& path, int nthreads) {
            OIIO::ImageBuf gbuf;
            DeepHandle deep;
            bool isDeep = false;
            std::string error;
            bool ok = false;
            {
                py::gil_scoped_release gil;
                ok = readGBuffer(path, nthreads, gbuf, deep, isDeep, error);
            }
            if (!ok) raiseError(error);
            if (isDeep) return py::cast(std::move(deep));
            return py::cast(Image::fromBuf(std::move(gbuf)));
        },
        "path"_a, py::kw_only(), "nthreads"_a = 0,
        R"(A flat dhdr G-buffer (dhdr-gbuffer's EXR) as dhdr-light reads it: every channel as float32
(image["N.X"], image["albedo.R"], ...), NaN and Inf replaced except in Z, the header (camera
matrices, name tables, Cryptomatte manifests) in image.attributes. A deep G-buffer (dhdr-gbuffer
--deep) comes as a DeepGBuffer, its samples sorted front to back, its non-finite values
other than Z replaced, as dhdr-light reads it.)");

    m.def(
        "read_channels",
        [](const std::string& path, int part) {
            OIIO::ImageBuf src;
            std::string error;
            {
                py::gil_scoped_release gil;
                src.reset(path, part, 0);
                if (!src.init_spec(path, part, 0))
                    error = cannotRead(path, src.geterror());
                else if (const std::string e =
                             pixelLimitError(src.spec().width, src.spec().height, src.spec().depth);
                         !e.empty())
                    error = path + ": " + e;
                else if (!src.read(part, 0, true, OIIO::TypeDesc::FLOAT))
                    error = cannotRead(path, src.geterror());
            }
            if (!error.empty()) raiseError(error);
            return Image::fromBuf(std::move(src));
        },
        "path"_a, py::kw_only(), "part"_a = 0,
        "Every channel of one part of a file, as float32, as it is (another renderer's passes).");

    m.def(
        "import_gbuffer",
        [](const py::object& passes, const std::string& channels) {
            Image storage;
            const ImageView src = view(asImage(passes, "passes", storage));
            ChannelMap map;
            std::string error;
            if (channels == "blender")
                map = blenderChannelMap();
            else if (!readChannelMap(channels, map, error))
                throw py::value_error(channels + ": " + error);
            OIIO::ImageBuf gbuf;
            std::vector<std::string> warnings;
            bool ok = false;
            {
                py::gil_scoped_release gil;
                ok = importGBuffer(src.buf, map, gbuf, warnings, error);
            }
            if (!ok) throw py::value_error("passes: " + error);
            for (const std::string& w : warnings)
                warn(w);
            return Image::fromBuf(std::move(gbuf));
        },
        "passes"_a, "channels"_a = "blender",
        R"(Another renderer's passes as a dhdr G-buffer (dhdr-light --channels): 'blender' maps
Cycles' Depth, Position, Normal (Z up) and the BaseColor, Roughness, Metallic AOVs (DiffCol
stands in for a missing BaseColor, with a warning); any other value is a channel-map JSON
file (docs/interop.md). The camera comes from the passes' worldToCamera and worldToNDC
attributes (set them with set_attribute when the file has none).)");

    m.def(
        "read_lights",
        [](const py::object& lights, bool radiometric) {
            const std::string text = formatLights(lightsOf(lights, radiometric));
            const py::object doc = py::module_::import("json").attr("loads")(text);
            return py::object(doc["lights"]);
        },
        "lights"_a, py::kw_only(), "radiometric"_a = false,
        "Lights (a lights file, a dict or a list of them) as the lights file's JSON objects: "
        "edit them and give them to light().");
}

} // namespace dhdr::python
