// Lights given from Python: a lights file's path, a light as a dict of that file's fields, or
// a list of either, in order (light() and bake_probes take them alike).
#pragma once

#include <dhdr/deferred/scene/lights.h>
#include <pybind11/pybind11.h>
#include <vector>

namespace dhdr::python {

// ValueError with the reader's message (naming the file or the light) when one is wrong;
// `radiometric` converts Blender's photometric intensities (toRadiometricUnits).
std::vector<Light> lightsOf(const pybind11::handle& given, bool radiometric);

} // namespace dhdr::python
