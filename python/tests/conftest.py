"""Shared fixtures: the built tools, generated inputs, and comparing files pixel for pixel."""
import os
import pathlib
import subprocess

import numpy as np
import OpenImageIO as oiio
import pytest

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
TOOLS = pathlib.Path(os.environ.get("DHDR_TOOLS_DIR", ROOT / "build" / "apps"))
TESTDATA = pathlib.Path(os.environ.get("DHDR_TESTDATA", ROOT / "testdata"))


def run_tool(name, *args, check=True):
    """Runs build/apps/NAME with ARGS; returns the CompletedProcess (stderr as text)."""
    result = subprocess.run([str(TOOLS / name), *map(str, args)], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError(f"{name} {' '.join(map(str, args))} failed:\n{result.stderr}")
    return result


def tool_error(result):
    """The message of 'dhdr-x: error: MESSAGE' on a tool's stderr."""
    line = [l for l in result.stderr.splitlines() if ": error: " in l][0]
    return line.split(": error: ", 1)[1]


def range_error_is_the_tools(call, tool, option, value, *args, keyword=None):
    """`call()` raises the ValueError TOOL --OPTION VALUE ARGS... exits 2 with, the option's
    name spelled as the keyword (by default the option's, '-' as '_'): 'phi: 0 is outside
    (0, 100]'."""
    # The value as the message prints it: a whole number in full, a real one as C's %g.
    text = str(value) if isinstance(value, int) else "%g" % value
    bad = run_tool(tool, *args, option, text, check=False)
    assert bad.returncode == 2, bad.stderr
    line = [l for l in bad.stderr.splitlines() if ": usage error: " in l][0]
    expected = line.split(": usage error: ", 1)[1]
    keyword = keyword or option[2:].replace("-", "_")
    assert expected.startswith(option + ": "), expected
    with pytest.raises(ValueError) as e:
        call()
    assert str(e.value) == keyword + expected[len(option):]


def read_file(path, dtype=None):
    """A file's pixels as OpenImageIO (not dhdr) reads them, in the file's own type by default:
    an independent reader for the comparisons. ImageInput, not ImageBuf, whose cache would
    give a file written again under the same name as it was; PNG's alpha left unassociated,
    as the file holds it."""
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    inp = oiio.ImageInput.open(str(path), config)
    assert inp, oiio.geterror()
    pixels = inp.read_image(dtype or inp.spec().format)
    inp.close()
    return pixels


def read_channels(path, names):
    """A file's channels `names`, in that order, as float32 (EXR keeps its own order)."""
    inp = oiio.ImageInput.open(str(path))
    assert inp, oiio.geterror()
    order = [list(inp.spec().channelnames).index(n) for n in names]
    pixels = inp.read_image(oiio.FLOAT)
    inp.close()
    return np.ascontiguousarray(pixels[..., order])


def write_exr(path, pixels, channels=None, dtype="float"):
    """Writes float pixels (h, w, c) with OpenImageIO (an independent writer)."""
    pixels = np.ascontiguousarray(pixels, dtype=np.float32)
    h, w, c = pixels.shape
    spec = oiio.ImageSpec(w, h, c, dtype)
    if channels:
        spec.channelnames = tuple(channels)
        if "A" in channels:
            spec.alpha_channel = channels.index("A")
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec), oiio.geterror()
    assert out.write_image(pixels)
    out.close()
    return path


def hdr_frame(seed=1, width=96, height=64, alpha=True, extra=0):
    """A scene-linear RGBA frame with a wide range (0.001 to 200), a few very bright pixels and
    some transparent ones, so every operator's shoulder, metering and bloom have work."""
    rng = np.random.default_rng(seed)
    rgb = np.exp(rng.uniform(np.log(1e-3), np.log(4.0), (height, width, 3))).astype(np.float32)
    rgb[rng.random((height, width)) < 0.01] *= 50.0
    channels = [rgb]
    if alpha:
        a = np.ones((height, width, 1), np.float32)
        a[:4, :4] = 0.0
        channels.append(a)
    if extra:
        channels.append(rng.random((height, width, extra)).astype(np.float32))
    return np.concatenate(channels, axis=2)


@pytest.fixture(scope="session")
def frame_exr(tmp_path_factory):
    return write_exr(tmp_path_factory.mktemp("in") / "frame.exr", hdr_frame(), list("RGBA"))


LIGHTS = TESTDATA / "cornell_box.lights.json"


@pytest.fixture(scope="session")
def gbuffer(tmp_path_factory):
    """A small G-buffer of the Cornell box, rendered by dhdr-gbuffer."""
    path = tmp_path_factory.mktemp("gbuf") / "g.exr"
    run_tool("dhdr-gbuffer", TESTDATA / "cornell_box.gltf", "--size", "64x48", "-o", path)
    return path
