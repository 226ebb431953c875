#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <dhdr/tonemap/display.h>

namespace dhdr {

bool encodeSRGB(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi, int nthreads) {
    return detail::mapColour(dst, src, roi, nthreads, [](const float* p, int, int) {
        return glm::vec3(srgbEncode(p[0]), srgbEncode(p[1]), srgbEncode(p[2]));
    });
}

} // namespace dhdr
