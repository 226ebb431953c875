#include <dhdr/deferred/gbuffer/shading_point.h>

namespace dhdr {

bool openGBuffer(const OIIO::ImageBuf& gbuf, GBufferPixels& out, OIIO::ImageBuf& errors) {
    const OIIO::ImageSpec& in = gbuf.spec();
    std::string message;
    if (!gbuffer::findLayout(in, out.layout, message)) {
        errors.errorfmt("no channel '{}' — is this a G-buffer?", message);
        return false;
    }
    if (!gbuffer::readCamera(in, out.camera, message)) {
        errors.errorfmt("{}", message);
        return false;
    }
    out.pixels = &gbuf;
    if (in.format != OIIO::TypeDesc::FLOAT || !gbuf.localpixels()) {
        out.floatCopy = gbuf.copy(OIIO::TypeDesc::FLOAT);
        out.pixels = &out.floatCopy;
    }
    return true;
}

} // namespace dhdr
