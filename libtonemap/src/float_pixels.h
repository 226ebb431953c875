// Direct float access to image pixels, which the operators use for their inner loops.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <functional>
#include <glm/glm.hpp>

namespace dhdr::detail {

// The pixels of `src` as a contiguous float array: `src`'s own memory when it already holds
// float pixels in memory, otherwise a converted copy owned by this object.
class FloatPixels {
public:
    explicit FloatPixels(const OIIO::ImageBuf& src);

    const float* at(int x, int y) const {
        return m_data + (size_t(y - m_ybegin) * m_width + size_t(x - m_xbegin)) * m_nchannels;
    }
    // Pixel (x, y) with coordinates clamped to the data window.
    const float* clamped(int x, int y) const;
    int nchannels() const { return m_nchannels; }

private:
    OIIO::ImageBuf m_copy;
    const float* m_data = nullptr;
    int m_xbegin = 0, m_ybegin = 0, m_xend = 0, m_yend = 0, m_width = 0, m_nchannels = 0;
};

// Makes `dst` ready to receive float pixels over `roi`: an uninitialized `dst` becomes a float
// image with `src`'s spec and metadata; an initialized one must be float and in memory.
// Sets `roi` to the region to process. On failure reports on `dst` and returns false.
bool prepareFloatDst(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI& roi,
                     int minChannels);

inline float* floatPixel(OIIO::ImageBuf& dst, int x, int y) {
    return static_cast<float*>(dst.pixeladdr(x, y));
}

// dst = f(src) on the colour channels over `roi`, f(pixel, x, y) → RGB; alpha and further
// channels copied. The shape of every per-pixel operator here.
bool mapColour(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi, int nthreads,
               const std::function<glm::vec3(const float*, int, int)>& f);

} // namespace dhdr::detail
