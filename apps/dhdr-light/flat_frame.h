// dhdr-light's flat G-buffers of the contract: read, lit and written strip by strip, so that
// memory stays at a strip's whatever the frame's size.
#pragma once

#include "whole_frame.h"

#include <dhdr/deferred/direct/ambient_occlusion.h>

namespace dhdr::app {

// The flat G-buffer `path` (part `part`) lit into `out`; `ssao`: the SSAO kernel when AO comes
// from the G-buffer (null: none). `lightFiles` is recorded in the output's header.
bool lightFlatGBuffer(const WholeFrameRun& run, const SsaoParams* ssao, const std::string& path,
                      int part, const std::string& out, const std::string& lightFiles);

} // namespace dhdr::app
