// Non-finite pixels, handled on purpose: counted, replaced and reported, never averaged.
#pragma once

#include <OpenImageIO/imagebuf.h>

namespace dhdr {

struct NonFiniteCount {
    long long nan = 0;
    long long positiveInf = 0;
    long long negativeInf = 0;
    long long negative = 0; // finite negatives, counted (and zeroed) only when asked
    long long total() const { return nan + positiveInf + negativeInf + negative; }
    NonFiniteCount& operator+=(const NonFiniteCount& o) {
        nan += o.nan;
        positiveInf += o.positiveInf;
        negativeInf += o.negativeInf;
        negative += o.negative;
        return *this;
    }
};

// What +Inf becomes: half's largest finite value, very bright yet far from float's overflow in
// any sum or filter downstream. A constant, so that the result of a pixel never depends on
// which other pixels were read with it (a strip, a tile).
inline constexpr float kInfinityReplacement = 65504.0f;

// Replaces, in the channels [roi.chbegin, roi.chend) of `img`, NaN and -Inf by 0 and +Inf by
// kInfinityReplacement, and with `zeroNegative` also finite negative values by 0 (colour that
// a display cannot show), each value on its own. Returns the counts of replaced values. `img`
// must hold float pixels (as dhdr's tools read).
NonFiniteCount replaceNonFinite(OIIO::ImageBuf& img, OIIO::ROI roi = {}, int nthreads = 0,
                                bool zeroNegative = false);

} // namespace dhdr
