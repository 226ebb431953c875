// import dhdr: the stages of the Deferred HDR Toolkit on numpy arrays (docs/python.md).
#include "py_image.h"

namespace dhdr::python {
void bindImageIO(py::module_& m);
void bindTonemap(py::module_& m);
void bindQuantize(py::module_& m);
void bindGeometryOps(py::module_& m);
void bindGBufferInput(py::module_& m);
void bindLighting(py::module_& m);
void bindDeep(py::module_& m);
void bindScene(py::module_& m);
void bindBakes(py::module_& m);
void bindBench(py::module_& m);
} // namespace dhdr::python

PYBIND11_MODULE(_dhdr, m) {
    m.doc() = "The Deferred HDR Toolkit's stages on images in memory: the same library calls as "
              "the dhdr-* tools, so a script and the command line give the same bits.";
    m.attr("__version__") = DHDR_VERSION;
    dhdr::python::bindImage(m);
    dhdr::python::bindImageIO(m);
    dhdr::python::bindTonemap(m);
    dhdr::python::bindQuantize(m);
    dhdr::python::bindGeometryOps(m);
    dhdr::python::bindDeep(m);
    dhdr::python::bindScene(m);
    dhdr::python::bindGBufferInput(m);
    dhdr::python::bindLighting(m);
    dhdr::python::bindBakes(m);
    dhdr::python::bindBench(m);
}
