#include <OpenImageIO/imageio.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_stamp.h>
#include <dhdr/deferred/scene/scene.h>

namespace dhdr::gbuffer {

void stampGBuffer(OIIO::ImageSpec& spec, const std::string& scenePath,
                  const std::optional<Moment>& moment) {
    spec.attribute("dhdr:source", scenePath);
    if (moment) writeMoment(spec, *moment);
    if (const std::string sha = sceneFingerprint(scenePath); !sha.empty())
        spec.attribute(kSceneFingerprint, sha);
}

} // namespace dhdr::gbuffer
