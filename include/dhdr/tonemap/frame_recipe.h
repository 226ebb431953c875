// dhdr-tonemap's recipe for one frame (docs/tonemap.md), for the tool (a whole frame or strip
// by strip) and dhdr.tonemap_frame alike: the frame as read is brought to scene-linear with
// what a display cannot show replaced (prepareFrame), tone-mapped with its metering, encoded
// for the display, and at most its R, G, B and alpha given in the output's type, quantized
// (PNG, TIFF, JPEG) or as floats (EXR) (toneMapFrame). ImageBufAlgo-shaped: each op as
// `bool op(dst, src, ..., roi, nthreads)` and as `ImageBuf op(src, ...)`.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/io/sanitize.h>
#include <dhdr/tonemap/display_transform.h>
#include <dhdr/tonemap/tone_map.h>

namespace dhdr {

struct FrameRecipe {
    ToneMapParams toneMap; // its stats: the metering to map with (null: src's own)
    const DisplayTransform* display = nullptr; // required
    // FLOAT: the display's values (what an EXR gets, written as half); UINT8 or UINT16: the
    // values quantized (quantize.h).
    OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT;
    bool dither = true; // ordered dither, on 8-bit output only
};

// `src` as read into scene-linear float in `dst` (which may be `src`): NaN and ±Inf replaced
// in colour and alpha, negative colour made 0 (a display shows no negative light; alpha keeps
// its negatives), then from the input's colour space (display.toSceneLinear). `replaced`,
// when given, receives what was replaced. What the tool meters and maps.
bool prepareFrame(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const DisplayTransform& display,
                  NonFiniteCount* replaced = nullptr, OIIO::ROI roi = {}, int nthreads = 0);
OIIO::ImageBuf prepareFrame(const OIIO::ImageBuf& src, const DisplayTransform& display,
                            NonFiniteCount* replaced = nullptr, OIIO::ROI roi = {},
                            int nthreads = 0);

// What a display is sent from an image of `hdr`: at most its R, G, B and alpha, in `type`,
// with `hdr`'s metadata.
OIIO::ImageSpec displaySpec(const OIIO::ImageSpec& hdr, OIIO::TypeDesc type);

// The recipe on prepared (scene-linear) `src` over `roi` (default: all of it): tone-mapped,
// encoded for the display and given in recipe.type into `dst` (made displaySpec(src,
// recipe.type) when uninitialized; else at most 4 channels of that type over `roi`, such as a
// strip of an output file). A strip gives the pixels the whole frame gives it, but
// reinhard-local, whose blur reaches across the frame, works on all of `src` at every call.
bool toneMapFrame(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const FrameRecipe& recipe,
                  OIIO::ROI roi = {}, int nthreads = 0);
OIIO::ImageBuf toneMapFrame(const OIIO::ImageBuf& src, const FrameRecipe& recipe,
                            OIIO::ROI roi = {}, int nthreads = 0);

// The recipe's last steps alone, on `src` tone-mapped already (toneMap with recipe.toneMap):
// what a whole frame mapped once is encoded with a strip at a time.
bool encodeFrame(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const FrameRecipe& recipe,
                 OIIO::ROI roi = {}, int nthreads = 0);

} // namespace dhdr
