// dhdr.DeepGBuffer: a deep G-buffer in memory (render_gbuffer(deep=True), read_gbuffer of a
// deep file), shaped like OpenImageIO's DeepData: per-pixel sample counts and the samples as
// one (samples, channels) float32 array, pixel after pixel, front to back.
#pragma once

#include "py_image.h"

#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <memory>

namespace dhdr::python {

struct DeepHandle {
    // Shared with every array handed out, which keep it alive.
    std::shared_ptr<DeepGBuffer> g = std::make_shared<DeepGBuffer>();
};

// The channels' types in a file (the deep contract's, then the motion layer's floats);
// ValueError when the channels are not a deep G-buffer's.
std::vector<OIIO::TypeDesc> deepFileFormats(const OIIO::ImageSpec& spec);

// Reads the deep part `part` of `path` as dhdr-light reads it (sorted front to back, non-finite
// values other than Z replaced). Call without the GIL; false with the tool's message.
bool readDeep(const std::string& path, int part, DeepGBuffer& out, std::string& error);

void bindDeep(py::module_& m);

} // namespace dhdr::python
