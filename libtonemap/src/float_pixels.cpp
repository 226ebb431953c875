#include "float_pixels.h"

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
    roi = OIIO::roi_intersection(roi, dst.roi());
    roi.chbegin = 0;
    roi.chend = std::min(dst.nchannels(), src.nchannels());
    return true;
}

} // namespace dhdr::detail
