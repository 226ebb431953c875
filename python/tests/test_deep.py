"""Deep G-buffers: render_gbuffer(deep=True), read_gbuffer of a deep file, write_gbuffer and
light() on a DeepGBuffer against dhdr-gbuffer --deep and dhdr-light, bit for bit."""
import numpy as np
import OpenImageIO as oiio
import pytest

import dhdr
from conftest import LIGHTS, TESTDATA, read_file, run_tool
from test_tonemap import same_bits

GLASS = str(TESTDATA / "cornell_glass.gltf")
ANIMATED = str(TESTDATA / "cornell_animated.gltf")
SIZE = (40, 30)


def read_deep(path, order):
    """A deep file as OpenImageIO's own Python module reads it (not dhdr's reader): its channel
    names, per-pixel counts (height, width) and the samples (total, channels `order`; EXR keeps
    its channels sorted by name) as float, pixel after pixel in the file's order."""
    inp = oiio.ImageInput.open(str(path))
    assert inp, oiio.geterror()
    spec = inp.spec()
    assert spec.deep
    dd = inp.read_native_deep_image()
    inp.close()
    names = list(spec.channelnames)
    counts = np.array([dd.samples(p) for p in range(dd.pixels)], np.uint32)
    rows = []
    for p in range(dd.pixels):
        for s in range(dd.samples(p)):
            rows.append([dd.deep_value_uint(p, c, s) if str(dd.channeltype(c)) == "uint"
                         else dd.deep_value(p, c, s) for c in range(len(names))])
    samples = np.array(rows, np.float32).reshape(-1, len(names))
    samples = np.ascontiguousarray(samples[:, [names.index(n) for n in order]])
    return sorted(names), counts.reshape(spec.height, spec.width), samples, spec


@pytest.fixture(scope="module")
def glass():
    return dhdr.Scene(GLASS)


@pytest.fixture(scope="module")
def tool_deep(tmp_path_factory):
    path = tmp_path_factory.mktemp("deep") / "tool.exr"
    run_tool("dhdr-gbuffer", GLASS, "--deep", "--size", f"{SIZE[0]}x{SIZE[1]}", "-o", path)
    return path


def test_render_deep_equals_tool(glass, tool_deep, tmp_path):
    g = dhdr.render_gbuffer(glass, size=SIZE, deep=True)
    assert isinstance(g, dhdr.DeepGBuffer) and (g.width, g.height) == SIZE
    names, counts, samples, spec = read_deep(tool_deep, g.channels)
    assert sorted(g.channels) == names
    names = g.channels
    np.testing.assert_array_equal(g.counts, counts)
    assert g.total_samples == len(samples) and counts.max() > 1  # glass: layers
    # Float channels hold the tool's very bits in memory; the file rounds the others to half.
    for c in ["Z", "ZBack", "P.X", "P.Y", "P.Z"]:
        same_bits(np.ascontiguousarray(g[c]), samples[:, names.index(c)])
    dhdr.write_gbuffer(str(tmp_path / "py.exr"), g)
    mine = read_deep(tmp_path / "py.exr", names)
    assert mine[0] == sorted(names)
    same_bits(mine[1], counts)
    same_bits(mine[2], samples)
    for key in ["worldToCamera", "worldToNDC", "dhdr:sceneSHA1", "dhdr:objectNames"]:
        assert mine[3].getattribute(key) == spec.getattribute(key), key
    # A pixel's samples, front to back, and the offsets' table.
    x, y = int(np.argmax(counts.max(axis=0))), int(np.argmax(counts.max(axis=1)))
    first = g.offsets[y * SIZE[0] + x]
    same_bits(g.pixel(x, y), g.samples[first:first + counts[y, x]])
    assert np.all(np.diff(g.pixel(x, y)[:, names.index("Z")]) >= 0)
    with pytest.raises(IndexError):
        g.pixel(SIZE[0], 0)
    with pytest.raises(KeyError, match="no channel 'Q'"):
        g["Q"]


def test_read_deep_gbuffer_is_the_file(tool_deep):
    g = dhdr.read_gbuffer(str(tool_deep))
    names, counts, samples, _ = read_deep(tool_deep, g.channels)
    assert isinstance(g, dhdr.DeepGBuffer) and sorted(g.channels) == names
    same_bits(g.counts, counts)
    same_bits(g.samples, samples)
    assert g.attributes["worldToCamera"] and "dhdr:materialNames" in g.attributes
    assert g.offsets[-1] == g.total_samples and not g.offsets.flags.writeable


@pytest.mark.parametrize("args, kwargs", [
    ([], {}),
    (["--lights", LIGHTS, "--ao", "rt", "--ao-distance", "0.3", "--emissive-lights", "off"],
     dict(lights=str(LIGHTS), ao="rt", ao_distance=0.3, emissive_lights=False)),
])
def test_light_deep_equals_tool(glass, tool_deep, tmp_path, args, kwargs):
    run_tool("dhdr-light", tool_deep, "--scene", GLASS, *args, "--type", "float",
             "-o", tmp_path / "tool.exr")
    g = dhdr.read_gbuffer(str(tool_deep))
    lit = dhdr.light(g, scene=glass, **kwargs)
    assert lit.channels == ["R", "G", "B", "A"]
    same_bits(lit.pixels, read_file(tmp_path / "tool.exr"))
    # The dst form, into an Image's own pixels.
    dst = dhdr.Image(np.zeros((SIZE[1], SIZE[0], 4), np.float32), ["R", "G", "B", "A"])
    assert dhdr.light(dst, g, scene=glass, **kwargs)
    same_bits(dst.pixels, lit.pixels)


def test_deep_from_arrays_lights_as_read(glass, tool_deep):
    g = dhdr.read_gbuffer(str(tool_deep))
    built = dhdr.DeepGBuffer(g.counts, g.samples.copy(), g.channels,
                             {k: g.attributes[k] for k in ["worldToCamera", "worldToNDC"]})
    same_bits(dhdr.light(built, LIGHTS).pixels, dhdr.light(g, LIGHTS).pixels)
    # The whole header goes back in as it came out (name tables, vectors, matrices).
    whole = dhdr.DeepGBuffer(g.counts, g.samples, g.channels, g.attributes)
    assert whole.attributes == g.attributes
    # Editing the samples is what light() shades: white glass and walls light brighter.
    g2 = dhdr.read_gbuffer(str(tool_deep))
    for c in ["albedo.R", "albedo.G", "albedo.B"]:
        g2[c][:] = 1.0
    assert dhdr.light(g2, LIGHTS).pixels[..., :3].sum() > dhdr.light(g, LIGHTS).pixels[
        ..., :3].sum()
    with pytest.raises(ValueError, match="the counts add up to"):
        dhdr.DeepGBuffer(g.counts, g.samples[:-1], g.channels)
    with pytest.raises(ValueError, match="one column a channel"):
        dhdr.DeepGBuffer(g.counts, g.samples[:, :3])
    with pytest.raises(ValueError, match="ao='ssao' works on flat G-buffers"):
        dhdr.light(g, LIGHTS, ao="ssao")


def test_animated_deep_equals_tool(tmp_path):
    run_tool("dhdr-gbuffer", ANIMATED, "--deep", "--frame", "9", "--size", "32x24",
             "-o", tmp_path / "tool.exr")
    g = dhdr.render_gbuffer(dhdr.Scene(ANIMATED), size=(32, 24), deep=True, frame=9)
    assert g.channels[-4:] == ["motion.X", "motion.Y", "motion.Z", "motion.W"]
    names, counts, samples, spec = read_deep(tmp_path / "tool.exr", g.channels)
    assert sorted(g.channels) == names
    names = g.channels
    same_bits(g.counts, counts)
    for c in ["Z", "motion.X", "motion.Y", "motion.Z", "motion.W"]:
        same_bits(np.ascontiguousarray(g[c]), samples[:, names.index(c)])
    dhdr.write_gbuffer(str(tmp_path / "py.exr"), g)
    mine = read_deep(tmp_path / "py.exr", names)
    same_bits(mine[2], samples)
    for key in ["dhdr:animationTime", "dhdr:fps"]:
        assert mine[3].getattribute(key) == spec.getattribute(key), key


def test_light_samples_equal_tools_deep_out(glass, tool_deep, tmp_path):
    run_tool("dhdr-light", tool_deep, "--scene", GLASS, "--deep-out", tmp_path / "samples.exr",
             "--type", "float", "-o", tmp_path / "lit.exr")
    g = dhdr.read_gbuffer(str(tool_deep))
    lit = dhdr.light_samples(g, scene=glass)
    assert lit.channels == ["R", "G", "B", "A", "Z", "ZBack"]
    names, counts, samples, _ = read_deep(tmp_path / "samples.exr", lit.channels)
    same_bits(lit.counts, counts)
    same_bits(lit.samples, samples)
    same_bits(lit["Z"], np.ascontiguousarray(g["Z"]))
    with pytest.raises(ValueError, match="ao='ssao' works on flat G-buffers"):
        dhdr.light_samples(g, LIGHTS, ao="ssao")


def test_auto_deep_is_the_tools_default(glass, tool_deep, tmp_path):
    # The glass in view: deep, as dhdr-gbuffer without --deep or --flat writes it.
    run_tool("dhdr-gbuffer", GLASS, "--size", f"{SIZE[0]}x{SIZE[1]}", "-o", tmp_path / "a.exr")
    auto = dhdr.render_gbuffer(glass, size=SIZE, deep="auto")
    assert isinstance(auto, dhdr.DeepGBuffer)
    names, counts, samples, _ = read_deep(tmp_path / "a.exr", auto.channels)
    same_bits(auto.counts, counts)
    same_bits(np.ascontiguousarray(auto["Z"]), samples[:, auto.channels.index("Z")])
    # No glass in view (looking at the back wall's corner): flat.
    flat = dhdr.render_gbuffer(glass, size=(8, 8), deep="auto",
                               lookat=(0.0, 0.05, 0.5, 0.0, 0.05, 0.56))
    assert isinstance(flat, dhdr.Image) and flat["A"].sum() > 0
    box = dhdr.render_gbuffer(dhdr.Scene(str(TESTDATA / "cornell_box.gltf")), size=(8, 8),
                              deep="auto")
    assert isinstance(box, dhdr.Image)
    with pytest.raises(ValueError, match="deep must be"):
        dhdr.render_gbuffer(glass, size=(8, 8), deep="yes")


def test_pixel_samples_equal_tool(glass, tmp_path):
    # Several rays a pixel (--pixel-samples): the tool's deep file and render_gbuffer's samples,
    # bit for bit, each ray's share in sample.weight; lit, the same frame as dhdr-light's.
    run_tool("dhdr-gbuffer", GLASS, "--pixel-samples", "16", "--size", f"{SIZE[0]}x{SIZE[1]}",
             "-o", tmp_path / "rays.exr")
    g = dhdr.render_gbuffer(glass, size=SIZE, deep="auto", pixel_samples=16)
    assert isinstance(g, dhdr.DeepGBuffer) and "sample.weight" in g.channels
    names, counts, samples, _ = read_deep(tmp_path / "rays.exr", g.channels)
    same_bits(g.counts, counts)
    for c in ["Z", "P.X", "sample.id", "sample.weight"]:
        same_bits(np.ascontiguousarray(g[c]), samples[:, g.channels.index(c)])
    w = g["sample.weight"]
    assert set(np.unique(w)) <= {1.0, 1.0 / 16.0} and (w < 1).sum() > 16
    run_tool("dhdr-light", tmp_path / "rays.exr", "--scene", GLASS, "--gi", "direct", "--type",
             "float", "-o", tmp_path / "lit.exr")
    lit = dhdr.light(dhdr.read_gbuffer(str(tmp_path / "rays.exr")), scene=glass, gi="direct")
    same_bits(lit.pixels, read_file(tmp_path / "lit.exr"))
    for bad, message in [(dict(pixel_samples=15), "a square"),
                         (dict(pixel_samples=16, deep=False), "deep G-buffer"),
                         (dict(pixel_filter="tent"), "pixel_filter"),
                         (dict(filter_width=0.1), "filter_width")]:
        with pytest.raises(ValueError, match=message):
            dhdr.render_gbuffer(glass, size=SIZE, **{"deep": True, **bad})
