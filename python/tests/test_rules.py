"""The module keeps the tools' rules (issue 48): non-finite input read as the tools read it and
never returned, values the tools refuse refused, messages naming keywords, arrays taken as the
docs say, and an interpreter without numpy told so at import."""
import base64
import json
import os
import pathlib
import struct
import subprocess
import sys
import warnings

import numpy as np
import OpenImageIO as oiio
import pytest

import dhdr
from conftest import LIGHTS, TESTDATA, hdr_frame

MODULE_DIR = str(pathlib.Path(dhdr.__file__).resolve().parent.parent)


def with_non_finite(frame):
    """FRAME with NaN, +Inf and -Inf in R, G, B, and what the tools read instead of them (NaN
    and -Inf as 0, +Inf as 65504)."""
    bad, clean = frame.copy(), frame.copy()
    for (y, x, c), value, read in [((3, 5, 0), np.nan, 0.0), ((7, 9, 1), np.inf, 65504.0),
                                   ((10, 2, 2), -np.inf, 0.0), ((20, 30, 0), np.nan, 0.0)]:
        bad[y, x, c], clean[y, x, c] = value, read
    return bad, clean


def calm(call):
    """CALL's result, the RuntimeWarning about replaced values silenced."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return call()


COLOUR_CALLS = {
    "tone_map": lambda f: dhdr.tone_map(f, op="reinhard").pixels,
    "tone_map_hable": lambda f: dhdr.tone_map(f, op="hable", exposure=1.0).pixels,
    "bloom": lambda f: dhdr.bloom(f).pixels,
    "to_display": lambda f: dhdr.to_display(f).pixels,
    "quantize": lambda f: dhdr.quantize(f, bits=16),
    "motion_blur": lambda f: dhdr.motion_blur(
        f, motion=np.full(f.shape[:2] + (4,), 3.0, np.float32),
        depth=np.ones(f.shape[:2], np.float32), shutter=1.0, samples=5).pixels,
}


@pytest.mark.parametrize("name", sorted(COLOUR_CALLS))
def test_non_finite_input_is_read_as_the_tools_read_it(name):
    frame = hdr_frame(seed=3, width=48, height=32)
    bad, clean = with_non_finite(frame)
    given = bad.copy()
    with pytest.warns(RuntimeWarning, match="1 \\+Inf and 1 -Inf"):
        out = COLOUR_CALLS[name](given)
    assert np.isfinite(out.astype(np.float64)).all()
    np.testing.assert_array_equal(out, COLOUR_CALLS[name](clean))
    # The caller's array is left as it was.
    np.testing.assert_array_equal(given, bad)


def test_metering_and_adaptation_read_non_finite_as_the_tools():
    bad, clean = with_non_finite(hdr_frame(seed=4, width=48, height=32))
    stats = calm(lambda: dhdr.meter(bad))
    assert stats.log_average == dhdr.meter(clean).log_average
    nan_frame = np.full((8, 8, 3), np.nan, np.float32)
    adapted = calm(lambda: dhdr.adapt([nan_frame, clean], fps=24))
    assert all(np.isfinite(s.log_average) for s in adapted)
    assert adapted[1].log_average == dhdr.adapt([np.zeros((8, 8, 3), np.float32), clean],
                                                fps=24)[1].log_average
    with pytest.raises(ValueError, match=r"metered\[1\]: nan is not a finite luminance"):
        dhdr.adapt_luminance([0.5, float("nan")])
    with pytest.raises(ValueError, match=r"metered\[0\]: inf"):
        dhdr.adapt_luminance([float("inf")])


def test_depth_keeps_its_infinity():
    # Z is +Inf where there is no surface, by contract: it is not a colour to clean.
    frame = np.concatenate([np.ones((4, 4, 3), np.float32), np.full((4, 4, 1), np.inf,
                                                                    np.float32)], axis=2)
    img = dhdr.Image(frame, ["R", "G", "B", "Z"])
    out = dhdr.tone_map(img, op="none").pixels
    assert np.isposinf(out[..., 3]).all()


def test_values_the_tools_refuse_are_refused(tmp_path, gbuffer):
    g = dhdr.read_gbuffer(str(gbuffer))
    for background in [(float("nan"), 0, 0), (0, float("inf"), 0), (1e39, 0, 0)]:
        with pytest.raises(ValueError, match="^background: "):
            dhdr.light(g, str(LIGHTS), background=background)
    src = hdr_frame(width=8, height=4)
    for shape in [(4, 8, 3), (8, 4, 4), (4, 9, 4)]:
        with pytest.raises(ValueError, match=r"^dst: shape \(%d, %d, %d\) is not src's \(4, 8, "
                                             r"4\)" % shape):
            dhdr.quantize(np.zeros(shape, np.uint8), src)
    bad = tmp_path / "a?b.exr"
    for call in [lambda: dhdr.write(str(bad), src),
                 lambda: dhdr.write_gbuffer(str(bad), g)]:
        with pytest.raises(ValueError, match=r"^path: .*a\?b\.exr: an image whose name holds '\?'"):
            call()
    assert list(tmp_path.iterdir()) == []


def no_camera_scene(tmp_path):
    """A glTF of one triangle and no camera."""
    data = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
           "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
           "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64,"
                        + base64.b64encode(data).decode()}],
           "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0]}]}
    path = tmp_path / "tri.gltf"
    path.write_text(json.dumps(doc))
    return str(path)


def test_messages_name_keywords_not_options(tmp_path, gbuffer):
    scene = dhdr.Scene(no_camera_scene(tmp_path))
    with pytest.raises(ValueError) as e:
        dhdr.render_gbuffer(scene, size=(8, 8))
    assert "give one with lookat=, or frame_all=True" in str(e.value)
    assert "--" not in str(e.value)
    cornell = dhdr.Scene(str(TESTDATA / "cornell_box.gltf"))
    for frame, error in [(1.5, TypeError), (2 ** 63, ValueError), (-2 ** 70, ValueError),
                         ("3", TypeError)]:
        with pytest.raises(error, match="^frame: "):
            dhdr.render_gbuffer(cornell, size=(8, 8), frame=frame)
        with pytest.raises(error, match="^frame: "):
            cornell.posed(frame=frame)
    g = dhdr.read_gbuffer(str(gbuffer))
    with pytest.raises(ValueError, match=r"^specular_samples: 4097 is outside \[0, 4096\]$"):
        dhdr.light(g, str(LIGHTS), specular_samples=4097)
    # The value is checked before the rules between keywords (gi='path' needs a scene).
    with pytest.raises(ValueError, match=r"^spp: 0 is outside \[1, 65536\]$"):
        dhdr.light(g, str(LIGHTS), gi="path", spp=0)


def test_arrays_too_large_to_convert_name_the_argument():
    huge = np.lib.stride_tricks.as_strided(np.zeros(1, np.float64), shape=(1 << 20, 1 << 20, 3),
                                           strides=(0, 0, 0))
    with pytest.raises((MemoryError, ValueError), match="^src: "):
        dhdr.tone_map(huge)
    wide = np.lib.stride_tricks.as_strided(np.zeros(1, np.float32), shape=(1, 1 << 32, 3),
                                           strides=(0, 0, 0))
    with pytest.raises((MemoryError, ValueError), match="^src: "):
        dhdr.tone_map(wide)


@pytest.mark.parametrize("call", ["tone_map", "bloom", "to_display", "meter", "adapt",
                                  "prepare_frame", "tonemap_frame"])
def test_height_width_arrays_are_grey(call):
    grey = hdr_frame(seed=6, width=40, height=24)[..., 0]
    rgb = np.repeat(grey[..., None], 3, axis=2)
    run = {"tone_map": lambda a: dhdr.tone_map(a, op="hable").pixels,
           "bloom": lambda a: dhdr.bloom(a).pixels,
           "to_display": lambda a: dhdr.to_display(a).pixels,
           "meter": lambda a: dhdr.meter(a).log_average,
           "adapt": lambda a: dhdr.adapt([a, a])[1].log_average,
           "prepare_frame": lambda a: dhdr.prepare_frame(a).pixels,
           "tonemap_frame": lambda a: dhdr.tonemap_frame(a, bits=8)}[call]
    np.testing.assert_array_equal(run(grey), run(rgb))


def test_motion_arrays_of_any_numeric_type_and_layout():
    colour = hdr_frame(seed=7, width=32, height=24)
    motion = np.zeros((24, 32, 4), np.float32)
    motion[..., 0] = 4.0
    depth = np.ones((24, 32), np.float32)
    expected = dhdr.motion_blur(colour, motion=motion, depth=depth, shutter=1.0).pixels
    for m in [motion.astype(np.float64), motion.astype(np.int32), motion.astype(np.float16),
              np.asfortranarray(motion), np.concatenate([motion, motion], axis=1)[:, ::2]]:
        np.testing.assert_array_equal(
            dhdr.motion_blur(colour, motion=m, depth=depth, shutter=1.0).pixels, expected)


def test_tonemap_frame_takes_arrays_and_imagebufs():
    frame = hdr_frame(seed=8, width=32, height=24)
    expected = dhdr.tonemap_frame(dhdr.Image(frame), bits=8)
    np.testing.assert_array_equal(dhdr.tonemap_frame(frame, bits=8), expected)
    buf = oiio.ImageBuf(frame)
    np.testing.assert_array_equal(dhdr.tonemap_frame(buf, bits=8), expected)
    np.testing.assert_array_equal(dhdr.tone_map(buf).pixels, dhdr.tone_map(frame).pixels)


def test_import_without_numpy_names_the_interpreter():
    # An interpreter whose numpy cannot be imported (a pyenv or conda one) stands in here.
    code = "import sys; sys.modules['numpy'] = None; import dhdr"
    env = dict(os.environ, PYTHONPATH=MODULE_DIR)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert r.returncode != 0
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: dhdr was built for "), r.stderr
    assert "cannot import numpy" in last and sys.executable in last, r.stderr
