#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <dhdr/tonemap/frame_recipe.h>
#include <dhdr/tonemap/quantize.h>

namespace dhdr {

namespace {

// A thread's float scratch for the rows being encoded, kept from call to call so that its
// pixels are overwritten rather than allocated again (a strip at a time).
OIIO::ImageBuf& scratch() {
    thread_local OIIO::ImageBuf buf;
    return buf;
}

// `buf` as a float image of `spec`'s channels over `roi`'s rows and columns.
void fitScratch(OIIO::ImageBuf& buf, const OIIO::ImageSpec& spec, OIIO::ROI roi) {
    OIIO::ImageSpec want(roi.width(), roi.height(), spec.nchannels, OIIO::TypeDesc::FLOAT);
    want.channelnames = spec.channelnames;
    const OIIO::ImageSpec& have = buf.spec();
    if (!buf.initialized() || have.width != want.width || have.height != want.height ||
        have.nchannels != want.nchannels || have.format != OIIO::TypeDesc::FLOAT)
        buf.reset(want);
    buf.set_origin(roi.xbegin, roi.ybegin);
}

// Sizes `dst` for the display image of `src` when it is not yet, and settles the region.
bool prepareDisplayDst(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const FrameRecipe& recipe,
                       OIIO::ROI& roi) {
    if (!src.initialized() || src.nchannels() < 3 || !recipe.display) {
        dst.errorfmt("a frame needs at least three channels and a display transform");
        return false;
    }
    if (!roi.defined()) roi = src.roi();
    if (!dst.initialized()) dst.reset(displaySpec(src.spec(), recipe.type));
    roi.chbegin = 0;
    roi.chend = dst.nchannels();
    return true;
}

// Display-linear `linear` (a float scratch over `roi`, changed) encoded for the display and
// given to `dst` in its type.
bool encodeInPlace(OIIO::ImageBuf& dst, OIIO::ImageBuf& linear, const FrameRecipe& recipe,
                   OIIO::ROI roi, int nthreads) {
    recipe.display->toDisplay(linear, roi, nthreads);
    if (dst.spec().format == OIIO::TypeDesc::FLOAT)
        return OIIO::ImageBufAlgo::copy(dst, linear, OIIO::TypeUnknown, roi, nthreads);
    QuantizeParams quantizing;
    quantizing.dither = dst.spec().format == OIIO::TypeDesc::UINT8 && recipe.dither;
    return quantize(dst, linear, quantizing, roi, nthreads);
}

} // namespace

bool prepareFrame(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const DisplayTransform& display,
                  NonFiniteCount* replaced, OIIO::ROI roi, int nthreads) {
    if (&dst != &src) {
        OIIO::ImageSpec spec = src.spec();
        spec.set_format(OIIO::TypeDesc::FLOAT);
        spec.channelformats.clear();
        dst.reset(spec);
        if (!dst.copy_pixels(src)) return false;
    }
    if (!roi.defined()) roi = dst.roi();
    OIIO::ROI colour = roi, alpha = roi;
    colour.chend = 3;
    alpha.chbegin = 3;
    alpha.chend = std::min(dst.nchannels(), 4);
    NonFiniteCount counts = replaceNonFinite(dst, colour, nthreads, true);
    if (alpha.chend > alpha.chbegin) counts += replaceNonFinite(dst, alpha, nthreads, false);
    if (replaced) *replaced += counts;
    return display.toSceneLinear(dst, roi, nthreads);
}

OIIO::ImageBuf prepareFrame(const OIIO::ImageBuf& src, const DisplayTransform& display,
                            NonFiniteCount* replaced, OIIO::ROI roi, int nthreads) {
    OIIO::ImageBuf dst;
    if (!prepareFrame(dst, src, display, replaced, roi, nthreads) && !dst.has_error())
        dst.errorfmt("the display transform needs float pixels in memory");
    return dst;
}

OIIO::ImageSpec displaySpec(const OIIO::ImageSpec& hdr, OIIO::TypeDesc type) {
    const int nch = std::min(hdr.nchannels, 4);
    OIIO::ImageSpec spec = hdr;
    spec.nchannels = nch;
    spec.channelnames = {"R", "G", "B", "A"};
    spec.channelnames.resize(size_t(nch));
    spec.alpha_channel = nch == 4 ? 3 : -1;
    spec.z_channel = -1;
    spec.channelformats.clear();
    spec.set_format(type);
    return spec;
}

namespace {

// The recipe's steps after the first: `fill` writes the linear frame into the thread's scratch
// (every channel of `src`, so that the display transform steps over the pixels as it would
// over `src` itself), which is then encoded into `dst`.
template <class Fill>
bool throughScratch(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const FrameRecipe& recipe,
                    OIIO::ROI roi, int nthreads, Fill fill) {
    if (!prepareDisplayDst(dst, src, recipe, roi)) return false;
    OIIO::ImageBuf& linear = scratch();
    fitScratch(linear, src.spec(), roi);
    OIIO::ROI all = roi;
    all.chend = src.nchannels();
    if (!fill(linear, all)) {
        dst.errorfmt("{}", linear.geterror());
        return false;
    }
    return encodeInPlace(dst, linear, recipe, roi, nthreads);
}

} // namespace

bool toneMapFrame(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const FrameRecipe& recipe,
                  OIIO::ROI roi, int nthreads) {
    return throughScratch(dst, src, recipe, roi, nthreads,
                          [&](OIIO::ImageBuf& linear, OIIO::ROI all) {
                              return toneMap(linear, src, recipe.toneMap, all, nthreads);
                          });
}

OIIO::ImageBuf toneMapFrame(const OIIO::ImageBuf& src, const FrameRecipe& recipe, OIIO::ROI roi,
                            int nthreads) {
    OIIO::ImageBuf dst;
    toneMapFrame(dst, src, recipe, roi, nthreads);
    return dst;
}

bool encodeFrame(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const FrameRecipe& recipe,
                 OIIO::ROI roi, int nthreads) {
    return throughScratch(
        dst, src, recipe, roi, nthreads, [&](OIIO::ImageBuf& linear, OIIO::ROI all) {
            return OIIO::ImageBufAlgo::copy(linear, src, OIIO::TypeUnknown, all, nthreads);
        });
}

} // namespace dhdr
