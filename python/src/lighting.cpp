#include "image.h"
namespace dhdr::python {
void bindLighting(py::module_&) {}
} // namespace dhdr::python
