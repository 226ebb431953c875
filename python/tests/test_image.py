"""dhdr.Image and numpy: zero copy, conversions, errors, both call forms, reading and writing,
OpenImageIO interop, the GIL and leaks."""
import threading
import time

import numpy as np
import OpenImageIO as oiio
import pytest

import dhdr
from conftest import LIGHTS, TESTDATA, hdr_frame, read_file, run_tool, tool_error, write_exr
from test_tonemap import same_bits


def test_float32_arrays_are_not_copied():
    a = hdr_frame()
    img = dhdr.Image(a)
    assert np.shares_memory(img.pixels, a)
    assert img.channels == ["R", "G", "B", "A"] and (img.width, img.height) == (96, 64)
    a[0, 0, 0] = 7.0
    assert img.pixels[0, 0, 0] == 7.0
    assert np.shares_memory(img.channel("G"), a) and img["A"].shape == (64, 96)


def test_results_are_owned_by_a_capsule_not_copied():
    out = dhdr.tone_map(hdr_frame())
    # The library's ImageBuf is the array's memory: no copy on the way out.
    assert type(out.pixels.base).__name__ == "PyCapsule"
    assert out.pixels.flags["C_CONTIGUOUS"] and out.pixels.dtype == np.float32


def test_other_arrays_are_converted():
    a = hdr_frame()
    expected = dhdr.tone_map(a).pixels
    same_bits(dhdr.tone_map(a.astype(np.float64)).pixels, expected)
    fortran = np.asfortranarray(a)
    assert not fortran.flags["C_CONTIGUOUS"]
    same_bits(dhdr.tone_map(fortran).pixels, expected)
    same_bits(dhdr.tone_map(a[:, ::1]).pixels, expected)
    same_bits(dhdr.tone_map(np.concatenate([a, a], axis=1)[:, ::2]).pixels,
              dhdr.tone_map(np.ascontiguousarray(np.concatenate([a, a], axis=1)[:, ::2])).pixels)
    gray = dhdr.Image(np.ones((4, 5), np.uint8))
    assert gray.nchannels == 1 and gray.pixels.dtype == np.float32


@pytest.mark.parametrize("value, error, words", [
    (np.zeros(3, np.float32), ValueError, "got shape (3,)"),
    (np.zeros((2, 2, 2, 2), np.float32), ValueError, "got shape (2, 2, 2, 2)"),
    (np.zeros((0, 4, 3), np.float32), ValueError, "has no pixels"),
    (np.zeros((4, 4, 3), np.complex64), TypeError, "dtype complex64"),
    ("frame.exr", TypeError, "got str"),
])
def test_bad_arrays_are_refused_clearly(value, error, words):
    with pytest.raises(error) as e:
        dhdr.tone_map(value)
    assert str(e.value).startswith("src: ") and words in str(e.value)


def test_too_few_channels_and_names():
    with pytest.raises(RuntimeError, match="3 channels|channels"):
        dhdr.tone_map(np.ones((4, 4, 2), np.float32))
    with pytest.raises(ValueError, match="2 channel names for 3 channels"):
        dhdr.Image(np.ones((4, 4, 3), np.float32), ["R", "G"])
    with pytest.raises(KeyError, match="no channel 'Q'"):
        dhdr.Image(np.ones((4, 4, 3), np.float32)).channel("Q")


def test_dst_form_writes_in_place_and_within_roi():
    a = hdr_frame()
    whole = dhdr.tone_map(a, op="hable").pixels
    dst = dhdr.Image(np.zeros_like(a))
    view = dst.pixels
    assert dhdr.tone_map(dst, a, op="hable", roi=(10, 20, 5, 15)) is True
    assert np.shares_memory(dst.pixels, view)  # the caller's memory, written in place
    same_bits(view[5:15, 10:20], whole[5:15, 10:20])
    assert not view[:5].any() and not view[:, :10].any()
    roi = oiio.ROI(0, 96, 0, 64, 0, 3)  # OpenImageIO's ROI works too
    assert dhdr.tone_map(dst, a, op="hable", roi=roi)
    empty = dhdr.Image()
    assert dhdr.tone_map(empty, a, op="hable")
    same_bits(empty.pixels, whole)
    # A failure: False, and the message on dst.
    bad = dhdr.Image()
    assert dhdr.tone_map(bad, np.ones((4, 4, 2), np.float32)) is False
    assert bad.has_error() and "channels" in bad.geterror() and not bad.has_error()


def test_read_finds_layers_by_name_like_the_tools(tmp_path):
    # Blender's multilayer EXR: ViewLayer.Combined is the colour; other layers by name.
    frame = hdr_frame(extra=3)
    names = [f"ViewLayer.Combined.{c}" for c in "RGBA"] + [f"ViewLayer.Emit.{c}" for c in "RGB"]
    path = write_exr(tmp_path / "blender.exr", frame, names)
    assert dhdr.layers(str(path)) == ["ViewLayer.Combined", "ViewLayer.Emit"]
    combined = dhdr.read(str(path), keep_others=False)
    assert combined.channels == names[:4]  # the file's names, R, G, B, A first
    same_bits(combined.pixels, frame[..., :4])
    emit = dhdr.read(str(path), layer="Emit", keep_others=False)
    same_bits(emit.pixels, frame[..., 4:])
    run_tool("dhdr-tonemap", path, "--layer", "Emit", "-o", tmp_path / "tool.exr")
    dhdr.write(str(tmp_path / "py.exr"), dhdr.tonemap_frame(emit))
    same_bits(read_file(tmp_path / "py.exr"), read_file(tmp_path / "tool.exr"))
    bad = run_tool("dhdr-tonemap", path, "--layer", "Nope", "-o", tmp_path / "x.exr",
                   check=False)
    with pytest.raises(RuntimeError) as e:
        dhdr.read(str(path), layer="Nope")
    assert str(e.value) == tool_error(bad) and "ViewLayer.Emit" in str(e.value)


def test_read_nuke_rgba_layer(tmp_path):
    frame = hdr_frame(alpha=False, extra=1)
    path = write_exr(tmp_path / "nuke.exr", frame, ["depth.Z", "rgba.R", "rgba.G", "rgba.B"])
    img = dhdr.read(str(path), keep_others=False)
    same_bits(img.pixels, frame[..., [1, 2, 3]])


def test_write_never_holds_nan_or_inf(tmp_path):
    a = np.ones((4, 4, 3), np.float32)
    a[0, 0] = [np.nan, np.inf, -np.inf]
    a[1, 1, 0] = 1e6
    with pytest.warns(RuntimeWarning):
        dhdr.write(str(tmp_path / "x.exr"), a)
    back = read_file(tmp_path / "x.exr", oiio.FLOAT)
    assert np.isfinite(back).all() and back[0, 0, 0] == 0 and back[1, 1, 0] == 65504
    dhdr.write(str(tmp_path / "f.exr"), a[1:], type="float")
    same_bits(read_file(tmp_path / "f.exr"), a[1:])
    with pytest.raises(ValueError, match="type must be"):
        dhdr.write(str(tmp_path / "y.exr"), a, type="double")
    with pytest.raises(RuntimeError, match="y.exr"):
        dhdr.write(str(tmp_path / "no" / "y.exr"), a)


def test_imagebuf_interop(tmp_path):
    frame = hdr_frame()
    buf = oiio.ImageBuf(oiio.ImageSpec(96, 64, 4, oiio.HALF))
    buf.set_pixels(oiio.ROI.All, frame)
    img = dhdr.from_imagebuf(buf)
    assert img.channels == list("RGBA")
    same_bits(img.pixels, frame.astype(np.float16).astype(np.float32))
    back = dhdr.to_imagebuf(dhdr.tone_map(img))
    assert back.spec().format == oiio.FLOAT
    same_bits(back.get_pixels(oiio.FLOAT), dhdr.tone_map(img).pixels)
    assert oiio.ImageBufAlgo.computePixelStats(back).max[0] > 0


def test_attributes_and_metadata_pass_through():
    img = dhdr.Image(hdr_frame())
    img.set_attribute("worldToCamera", np.eye(4))
    img.set_attribute("dhdr:note", "plate 3")
    img.origin = (10, 20)
    out = dhdr.tone_map(img)
    assert out.attributes["dhdr:note"] == "plate 3"
    assert out.attributes["worldToCamera"][2] == (0.0, 0.0, 1.0, 0.0)
    assert out.origin == (10, 20)
    same_bits(dhdr.tone_map(img, roi=(10, 106, 20, 84)).pixels, out.pixels)


@pytest.mark.parametrize("stage", ["tone_map", "render_gbuffer", "light", "render_animated",
                                   "light_deep"])
def test_gil_is_released_while_a_stage_runs(stage, gbuffer):
    big = np.tile(hdr_frame(), (8, 8, 1))  # 768 x 512
    scene = dhdr.Scene(str(TESTDATA / "cornell_box.gltf"))
    g = dhdr.read_gbuffer(str(gbuffer))
    if stage == "light_deep":
        glass = dhdr.Scene(str(TESTDATA / "cornell_glass.gltf"))
        deep = dhdr.render_gbuffer(glass, size=(256, 256), deep=True)
    calls = {
        "tone_map": lambda: dhdr.tone_map(big, op="reinhard-local", nthreads=1),
        "render_gbuffer": lambda: dhdr.render_gbuffer(scene, size=(512, 512), nthreads=1),
        "light": lambda: dhdr.light(g, str(LIGHTS), scene=scene, ao="rt", nthreads=1),
        "render_animated": lambda: dhdr.render_gbuffer(
            dhdr.Scene(str(TESTDATA / "cornell_animated.gltf")), size=(512, 512), frame=5,
            nthreads=1),
        "light_deep": lambda: dhdr.light(deep, str(LIGHTS), scene=glass, ao="rt", nthreads=1),
    }
    window = []

    def work():
        t0 = time.perf_counter()
        calls[stage]()
        window.extend([t0, time.perf_counter()])

    thread = threading.Thread(target=work)
    stamps = []
    thread.start()
    while thread.is_alive():
        stamps.append(time.perf_counter())
    t0, t1 = window
    # Holding the GIL, the call would let no step of this loop run between t0 and t1.
    inside = sum(t0 < t < t1 for t in stamps)
    assert inside > 1000, (inside, t1 - t0)


def rss_kib():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) for l in f if l.startswith("VmRSS"))


def test_no_leak_over_a_thousand_calls(gbuffer, tmp_path):
    a = np.tile(hdr_frame(), (2, 2, 1))  # 192 x 128 x 4: 393 KB a result
    g = dhdr.read_gbuffer(str(gbuffer))
    lights = dhdr.read_lights(str(LIGHTS))

    def calls(n):
        for _ in range(n):
            out = dhdr.tone_map(a)
            dst = dhdr.Image()
            dhdr.bloom(dst, out)
            dhdr.quantize(dhdr.to_display(dst))
            dhdr.meter(dhdr.Image(a))
            dhdr.edge_aa(dhdr.light(g, lights), gbuffer=g)
            dhdr.write(str(tmp_path / "x.exr"), dhdr.read(str(gbuffer), layer="albedo", keep_others=False))

    calls(100)
    before = rss_kib()
    calls(1000)
    grown = rss_kib() - before
    # Leaking one result a call would be 393 MB.
    assert grown < 8 * 1024, f"RSS grew by {grown} KiB over 1000 calls"


def test_no_leak_with_deep_gbuffers(tmp_path):
    # 40 x 30 of glass: 880 samples, 116 KB of them a read.
    run_tool("dhdr-gbuffer", TESTDATA / "cornell_glass.gltf", "--deep", "--size", "40x30",
             "-o", tmp_path / "deep.exr")
    lights = dhdr.read_lights(str(LIGHTS))

    def calls(n):
        for _ in range(n):
            g = dhdr.read_gbuffer(str(tmp_path / "deep.exr"))
            views = g.samples, g["Z"], g.pixel(20, 15), g.offsets, g.counts
            built = dhdr.DeepGBuffer(g.counts, views[0], g.channels, g.attributes)
            dhdr.light(built, lights)
            del g, views, built

    calls(100)
    before = rss_kib()
    calls(1000)
    grown = rss_kib() - before
    assert grown < 8 * 1024, f"RSS grew by {grown} KiB over 1000 calls"
