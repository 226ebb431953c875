// Display-referred values to integer pixels, with ordered dithering against banding.
#pragma once

#include <OpenImageIO/imagebuf.h>

namespace dhdr {

struct QuantizeParams {
    // Ordered dithering of the colour channels (the first three) before rounding: an offset in
    // (−½, ½) step from the 8 × 8 Bayer matrix, so that a smooth gradient neither bands nor
    // biases (the offsets average to 0 over every 8 × 8 tile). The offset depends only on the
    // pixel's position: deterministic whatever the thread count, and repetitive enough for PNG
    // to compress (random noise doubled the encoding time).
    bool dither = true;
};

// dst = round(clamp(src, 0, 1) · (2^bits − 1) + offset), with bits 8 or 16 from dst's format
// (UINT8 or UINT16) and offset 0 on alpha and further channels or without dithering.
// `dst` must be initialized, in memory (its own pixels or a wrapped buffer, such as one strip
// of an output file), with at most as many channels as `src`; `src` must hold float pixels
// in memory over `roi` (default: dst's region). The Bayer phase follows absolute coordinates,
// so a strip gives the same pixels as the whole image.
bool quantize(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const QuantizeParams& params = {},
              OIIO::ROI roi = {}, int nthreads = 0);

} // namespace dhdr
