#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>

namespace dhdr::detail {

using OIIO::ImageBuf;
using OIIO::ImageSpec;
using OIIO::ROI;
using OIIO::TypeDesc;

FloatPixels::FloatPixels(const ImageBuf& src) {
    const ImageSpec& spec = src.spec();
    const ImageBuf* pixels = &src;
    if (spec.format != TypeDesc::FLOAT || !src.localpixels()) {
        ImageSpec floatSpec = spec;
        floatSpec.set_format(TypeDesc::FLOAT);
        m_copy.reset(floatSpec);
        m_copy.copy_pixels(src);
        pixels = &m_copy;
    }
    m_data = static_cast<const float*>(pixels->localpixels());
    m_xbegin = spec.x;
    m_ybegin = spec.y;
    m_xend = spec.x + spec.width;
    m_yend = spec.y + spec.height;
    m_width = spec.width;
    m_nchannels = spec.nchannels;
}

const float* FloatPixels::clamped(int x, int y) const {
    return at(std::clamp(x, m_xbegin, m_xend - 1), std::clamp(y, m_ybegin, m_yend - 1));
}

bool prepareFloatDst(ImageBuf& dst, const ImageBuf& src, ROI& roi, int minChannels) {
    if (!src.initialized()) {
        dst.errorfmt("source image is empty");
        return false;
    }
    if (src.nchannels() < minChannels) {
        dst.errorfmt("source image has {} channels, needs at least {}", src.nchannels(),
                     minChannels);
        return false;
    }
    if (!roi.defined()) roi = src.roi();
    if (!dst.initialized()) {
        ImageSpec spec = src.spec();
        spec.set_format(TypeDesc::FLOAT);
        spec.channelformats.clear();
        dst.reset(spec);
        // Whatever the operator does not touch is the source's.
        dst.copy_pixels(src);
    } else if (dst.spec().format != TypeDesc::FLOAT || !dst.localpixels()) {
        dst.errorfmt("destination must hold float pixels in memory");
        return false;
    }
    // The caller's channel range, within both images: edge AA filters colour only.
    const int chbegin = std::max(roi.chbegin, 0);
    const int chend = std::min({roi.chend, dst.nchannels(), src.nchannels()});
    roi = OIIO::roi_intersection(roi, dst.roi());
    roi.chbegin = chbegin;
    roi.chend = std::max(chbegin, chend);
    return true;
}

bool mapColour(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi, int nthreads,
               const std::function<glm::vec3(const float*, int, int)>& f) {
    if (!prepareFloatDst(dst, src, roi, 3)) return false;
    if (dst.nchannels() < 3) {
        dst.errorfmt("destination has {} channels, needs at least 3", dst.nchannels());
        return false;
    }
    const FloatPixels in(src);
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float* p = in.at(x, y);
                float* q = floatPixel(dst, x, y);
                const glm::vec3 c = f(p, x, y);
                q[0] = c.r;
                q[1] = c.g;
                q[2] = c.b;
                for (int k = 3; k < r.chend; ++k)
                    q[k] = p[k];
            }
    });
    return true;
}

} // namespace dhdr::detail
