// Non-finite pixels, handled on purpose: counted, replaced and reported, never averaged.
#pragma once

#include <OpenImageIO/imagebuf.h>

namespace dhdr {

struct NonFiniteCount {
    long long nan = 0;
    long long positiveInf = 0;
    long long negativeInf = 0;
    long long total() const { return nan + positiveInf + negativeInf; }
};

// Replaces, in the channels [roi.chbegin, roi.chend) of `img`, NaN and -Inf by 0 and +Inf by
// the largest finite value found in that channel (0 if there is none). Returns the counts of
// replaced values. `img` must hold float pixels (as read by dhdr's tools).
NonFiniteCount replaceNonFinite(OIIO::ImageBuf& img, OIIO::ROI roi = {}, int nthreads = 0);

} // namespace dhdr
