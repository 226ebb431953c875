// The largest image any reader of dhdr takes, checked before pixels are read or allocated:
// a file's header can claim any size (a 65536 x 65536 EXR of constant pixels is a few MB).
#pragma once

#include <string>

namespace dhdr {

// The most pixels (width × height) an image a tool reads or renders may have unless
// --max-pixels raises it: 16384 × 16384, so that a 16K frame (15360 × 8640) passes and a
// 65536 × 65536 file (a few MB of ZIP-compressed constant pixels) is refused before it is
// streamed for minutes. 0 lifts the limit.
inline constexpr long long kDefaultMaxPixels = 16384LL * 16384LL;
// The limit in force, for the whole process: kDefaultMaxPixels until set (the tools set it
// from --max-pixels).
long long maxPixels();
void setMaxPixels(long long pixels);
// Empty when an image of width × height (× depth) pixels is within maxPixels(); else
// "WxH pixels is more than --max-pixels N (SxS); give --max-pixels to raise it", which a
// caller puts after the file's name.
std::string pixelLimitError(long long width, long long height, long long depth = 1);
// Whether `error` is one pixelLimitError made (it names the file without "cannot read").
bool isPixelLimitError(const std::string& error);

} // namespace dhdr
