"""The Deferred HDR Toolkit's stages on images in memory (docs/python.md)."""
import sys as _sys

from . import _built_for

# Every call takes and gives numpy arrays, and the compiled part fits one Python version: an
# interpreter other than the one the module was built for (a pyenv or conda one) fails here,
# naming both, not at its first call.
_BUILT_FOR = (f"dhdr was built for {_built_for.INTERPRETER} (Python {_built_for.VERSION}); "
              f"this is {_sys.executable} (Python {_sys.version.split()[0]})")
try:
    import numpy as _numpy  # noqa: F401
except ImportError as e:
    raise ImportError(f"{_BUILT_FOR}, which cannot import numpy ({e}): run "
                      f"{_built_for.INTERPRETER}, or build dhdr with -DPython3_EXECUTABLE="
                      f"{_sys.executable} once numpy is installed there") from e
try:
    from ._dhdr import *  # noqa: F401,F403
except ImportError as e:
    raise ImportError(f"{_BUILT_FOR}, which cannot load the compiled module ({e})") from e
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
