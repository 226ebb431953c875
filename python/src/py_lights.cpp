// Lights given from Python (py_lights.h): files, dicts and lists of both, read by the lights
// file's own parser after their nesting is checked.
#include "py_lights.h"

#include "py_image.h"

#include <algorithm>
#include <dhdr/deferred/scene/lights.h>
#include <string>
#include <vector>

namespace dhdr::python {

namespace {

// Lights from a lights file's path, a light as a dict (the file's JSON object), or a list of
// either, in order. A dict, or a list of dicts only, is read as a lights file holding them
// would be (environment images relative to the working directory, their suns after them).
void addLights(const py::handle& given, bool radiometric, std::vector<Light>& lights) {
    std::vector<Light> more;
    std::string error;
    std::vector<std::string> warnings;
    const bool sequence = py::isinstance<py::list>(given) || py::isinstance<py::tuple>(given);
    bool dicts = py::isinstance<py::dict>(given);
    if (sequence) {
        dicts = py::len(given) > 0;
        for (const py::handle& item : given)
            dicts = dicts && py::isinstance<py::dict>(item);
    }
    if (py::isinstance<py::str>(given) ||
        py::isinstance(given, py::module_::import("os").attr("PathLike"))) {
        const std::string path = py::str(given);
        bool ok = false;
        {
            py::gil_scoped_release gil;
            ok = readLightsFile(path, more, error, warnings);
        }
        if (!ok) throw py::value_error(error);
    } else if (dicts) {
        // One light, a file's object ({"lights": [...]}) or a list of lights.
        const bool document = !sequence && py::cast<py::dict>(given).contains("lights");
        const py::object doc = document   ? py::reinterpret_borrow<py::object>(given)
                               : sequence ? py::reinterpret_borrow<py::object>(given)
                                          : py::object(py::make_tuple(given));
        const std::string text =
            py::str(py::module_::import("json").attr("dumps")(document ? doc : py::list(doc)));
        bool ok = parseLights(text, more, error);
        if (ok) {
            py::gil_scoped_release gil;
            ok = loadEnvironmentImages(more, "", error, warnings);
        }
        if (!ok) throw py::value_error("lights: " + error);
    } else if (sequence) {
        for (const py::handle& item : given)
            addLights(item, radiometric, lights);
        return;
    } else {
        throw py::type_error("lights: expected a lights file, a light (dict) or a list of them");
    }
    for (const std::string& w : warnings)
        warn(w);
    if (radiometric) toRadiometricUnits(more);
    lights.insert(lights.end(), more.begin(), more.end());
}

// Deeper than any lights document goes ({"lights": [{"color": [...]}]} is 4 levels).
constexpr int kMaxLightsNesting = 32;

// Walks the dicts, lists and tuples of `given` before anything recurses through them (addLights,
// json.dumps): one that holds itself, or nesting past kMaxLightsNesting, is a ValueError
// instead of a recursion that ends in a stack overflow.
void checkNesting(const py::handle& given, std::vector<const PyObject*>& path) {
    const bool dict = py::isinstance<py::dict>(given);
    if (!dict && !py::isinstance<py::list>(given) && !py::isinstance<py::tuple>(given)) return;
    if (std::find(path.begin(), path.end(), given.ptr()) != path.end())
        throw py::value_error("lights: a list or dict that holds itself");
    if (int(path.size()) >= kMaxLightsNesting)
        throw py::value_error("lights: nested more than " + std::to_string(kMaxLightsNesting) +
                              " lists or dicts deep");
    path.push_back(given.ptr());
    if (dict)
        for (const auto& item : py::reinterpret_borrow<py::dict>(given))
            checkNesting(item.second, path);
    else
        for (const py::handle& item : given)
            checkNesting(item, path);
    path.pop_back();
}

} // namespace

std::vector<Light> lightsOf(const py::handle& given, bool radiometric) {
    std::vector<const PyObject*> path;
    checkNesting(given, path);
    std::vector<Light> lights;
    addLights(given, radiometric, lights);
    return lights;
}

} // namespace dhdr::python
