// What a G-buffer records in its header besides its channels (docs/gbuffer.md, header): the
// scene file it was rendered from, that file's fingerprint, and for an animated scene the
// moment it shows. dhdr-gbuffer, its deep files and render_gbuffer stamp it here, so that
// dhdr-light can tell whether --scene is that file and pose it where the pixels are.
#pragma once

#include <dhdr/deferred/gbuffer/gbuffer_time.h>
#include <optional>
#include <string>

namespace dhdr::gbuffer {

// Writes dhdr:source (`scenePath`), the moment when the scene played (writeMoment; none: it
// stands still) and kSceneFingerprint (when the file can be read) into `spec`, in that order.
void stampGBuffer(OIIO::ImageSpec& spec, const std::string& scenePath,
                  const std::optional<Moment>& moment);

} // namespace dhdr::gbuffer
