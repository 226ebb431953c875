// dhdr._dhdr._library_call_ms: a stage's library call timed in C++ inside this process, on the same
// memory the Python call gets (bench/python_overhead.py alternates it with the Python call,
// so that the shared machine's load falls on both alike). Not part of the module's API.
#include "py_lights.h"
#include "py_ops.h"

#include <chrono>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/tonemap/bloom.h>
#include <dhdr/tonemap/edge_aa.h>
#include <dhdr/tonemap/tone_map.h>

namespace dhdr::python {

void bindBench(py::module_& m) {
    using namespace pybind11::literals;
    m.def(
        "_library_call_ms",
        [](const std::string& stage, const py::object& src, const py::object& normal,
           const py::object& depth, const py::object& lights, int nthreads) {
            Image s0, s1, s2;
            const ImageView in = view(asImage(src, "src", s0));
            ImageView n, z;
            if (!normal.is_none()) n = view(asImage(normal, "normal", s1));
            if (!depth.is_none()) z = view(asImage(depth, "depth", s2));
            const std::vector<Light> list =
                lights.is_none() ? std::vector<Light>{} : lightsOf(lights, false);
            double ms = 0.0;
            bool ok = false;
            {
                py::gil_scoped_release gil;
                const auto t = std::chrono::steady_clock::now();
                {
                    // A new destination each call, as the return form makes.
                    OIIO::ImageBuf dst;
                    if (stage == "light")
                        ok = shadeGBuffer(dst, in.buf, LightingInputs{list, nullptr}, {}, {},
                                          nthreads);
                    else if (stage == "tone_map")
                        ok = toneMap(dst, in.buf, {}, {}, nthreads);
                    else if (stage == "bloom")
                        ok = bloom(dst, in.buf, {}, {}, nthreads);
                    else if (stage == "edge_aa")
                        ok = edgeAA(dst, in.buf, &n.buf, &z.buf, {}, {}, nthreads);
                }
                ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t)
                         .count();
            }
            if (!ok) raiseError("_library_call_ms: " + stage + " failed");
            return ms;
        },
        "stage"_a, "src"_a, "normal"_a = py::none(), "depth"_a = py::none(),
        "lights"_a = py::none(), "nthreads"_a = 0,
        "Benchmark hook: the library call of light, tone_map, bloom or edge_aa timed in C++ "
        "(milliseconds), for bench/python_overhead.py.");
}

} // namespace dhdr::python
