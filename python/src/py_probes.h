// dhdr.Probes: a baked probe volume in memory (bake_probes without a file, read_probes), which
// light(probes=...) takes as it takes a dhdr-probes file.
#pragma once

#include <dhdr/deferred/gi/probes.h>
#include <memory>
#include <pybind11/pybind11.h>

namespace dhdr::python {

struct ProbesHandle {
    std::shared_ptr<const ProbeVolume> volume;
    int lights = -1; // the lights the bake lit with; −1: read from a file, not known
};

// light()'s probes=: "" or None (none), a dhdr-probes file's path, or a dhdr.Probes. Reads a
// file without the GIL; ValueError naming the file when it is not a probe volume.
std::shared_ptr<const ProbeVolume> probesOf(const pybind11::handle& given);

} // namespace dhdr::python
