"""The Deferred HDR Toolkit's stages on images in memory (docs/python.md)."""
from ._dhdr import *  # noqa: F401,F403
from ._dhdr import __version__, Image


def prepare_frame(src, *, config="", colorspace="", nthreads=0):
    """dhdr-tonemap's reading of a frame, on a copy of src (an Image as dhdr.read gives it):
    non-finite and negative colour replaced (NaN, -Inf and negatives by 0, +Inf by 65504;
    alpha's non-finite values too), then brought to scene-linear from colorspace (or sRGB
    when the image says so: to_scene_linear). What the tool meters and maps."""
    img = src.copy()
    w, h = img.width, img.height
    replace_non_finite(img, zero_negative=True, roi=(0, w, 0, h, 0, 3), nthreads=nthreads)
    if img.nchannels > 3:
        replace_non_finite(img, roi=(0, w, 0, h, 3, 4), nthreads=nthreads)
    to_scene_linear(img, img, config=config, colorspace=colorspace, nthreads=nthreads)
    return img


def tonemap_frame(src, *, stats=None, config="", colorspace="", display="", view="", look="",
                  bits=None, dither=True, nthreads=0, **tone):
    """dhdr-tonemap on one frame in memory: what the tool does between reading and writing.

    src (an Image as dhdr.read gives it, left unchanged) is prepared as the tool reads it
    (prepare_frame), tone-mapped (tone_map with the keywords in `tone` and `stats`, e.g. one
    of dhdr.adapt's), and encoded for the display (to_display; op='aces' defaults the view to
    ACES, as --op aces does). With bits=8 or 16 the result is quantize()'s integer array
    (what PNG and TIFF get; dither applies to 8 bits only, as in the tool), else the float
    Image an EXR gets (at most R, G, B, A).
    """
    ocio = dict(config=config, colorspace=colorspace)
    img = prepare_frame(src, **ocio, nthreads=nthreads)
    img = tone_map(img, stats=stats, nthreads=nthreads, **tone)
    to_display(img, img, **ocio, display=display, look=look, nthreads=nthreads,
               view=view or ("ACES" if tone.get("op") == "aces" else ""))
    if img.nchannels > 4:
        img = Image(img.pixels[:, :, :4], img.channels[:4])
    if bits is None:
        return img
    return quantize(img, bits=bits, dither=dither and bits == 8, nthreads=nthreads)


def from_imagebuf(buf):
    """An OpenImageIO.ImageBuf as an Image: its pixels as float32 (one copy), its channel
    names and origin."""
    import OpenImageIO as oiio
    if buf.has_error:
        raise RuntimeError(buf.geterror())
    spec = buf.spec()
    image = Image(buf.get_pixels(oiio.FLOAT), list(spec.channelnames))
    image.origin = (spec.x, spec.y)
    return image


def to_imagebuf(image):
    """An Image as a float OpenImageIO.ImageBuf (one copy), channel names and origin kept."""
    import OpenImageIO as oiio
    spec = oiio.ImageSpec(image.width, image.height, image.nchannels, oiio.FLOAT)
    spec.channelnames = tuple(image.channels)
    spec.x, spec.y = image.origin
    spec.full_x, spec.full_y = image.origin
    buf = oiio.ImageBuf(spec)
    if not buf.set_pixels(oiio.ROI.All, image.pixels):
        raise RuntimeError(buf.geterror())
    return buf
