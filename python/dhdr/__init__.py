"""The Deferred HDR Toolkit's stages on images in memory (docs/python.md)."""
from ._dhdr import *  # noqa: F401,F403
from ._dhdr import __version__, Image


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
