"""The lighting stage from Python against dhdr-light on the same G-buffer, bit for bit."""
import json

import numpy as np
import OpenImageIO as oiio
import pytest

import dhdr
from conftest import LIGHTS, TESTDATA, read_channels, run_tool, tool_error, write_exr
from test_tonemap import same_bits



def light_tool(gbuffer, out, *args, channels=tuple("RGBA")):
    run_tool("dhdr-light", gbuffer, *args, "--type", "float", "-o", out)
    return read_channels(out, channels)


def test_gbuffer_channels_and_header(gbuffer):
    g = dhdr.read_gbuffer(str(gbuffer))
    assert (g.width, g.height) == (64, 48)
    for name in ["A", "Z", "P.X", "N.X", "albedo.R", "roughness", "id.object"]:
        assert g[name].shape == (48, 64)
    header = g.attributes
    assert len(header["worldToCamera"]) == 4 and len(header["worldToNDC"]) == 4
    assert np.isinf(g["Z"][g["A"] == 0]).all()  # the contract's background depth
    # The name tables, id 0 the background, as OpenImageIO reads them from the file.
    spec = oiio.ImageInput.open(str(gbuffer)).spec()
    assert header["dhdr:objectNames"] == list(spec.getattribute("dhdr:objectNames"))
    assert header["dhdr:objectNames"][0] == "" and "floor" in header["dhdr:objectNames"]
    assert any(k.endswith("/manifest") and "floor" in v for k, v in header.items())


def test_light_equals_tool(gbuffer, tmp_path):
    expected = light_tool(gbuffer, tmp_path / "tool.exr", "--lights", LIGHTS)
    mine = dhdr.light(dhdr.read_gbuffer(str(gbuffer)), str(LIGHTS))
    assert mine.channels == list("RGBA")
    same_bits(mine.pixels, expected)


def test_light_options_equal_tool(gbuffer, tmp_path):
    expected = light_tool(gbuffer, tmp_path / "tool.exr", "--lights", LIGHTS, "--ao", "ssao",
                          "--ao-distance", "0.2", "--aovs", "--background", "0.1,0.2,0.3",
                          "--diffuse", "burley", "--tile", "8", "--brute-force",
                          channels=["R", "G", "B", "A", "AO", "Z", "N.X", "N.Y", "N.Z"])
    mine = dhdr.light(dhdr.read_gbuffer(str(gbuffer)), str(LIGHTS), ao="ssao", ao_distance=0.2,
                      aovs=True, background=(0.1, 0.2, 0.3), diffuse="burley", tile=8,
                      brute_force=True)
    assert mine.channels == ["R", "G", "B", "A", "AO", "Z", "N.X", "N.Y", "N.Z"]
    same_bits(mine.pixels, expected)


def test_lights_as_python_objects(gbuffer, tmp_path):
    g = dhdr.read_gbuffer(str(gbuffer))
    lights = dhdr.read_lights(str(LIGHTS))
    assert all(isinstance(l, dict) and "type" in l for l in lights)
    same_bits(dhdr.light(g, lights).pixels, dhdr.light(g, str(LIGHTS)).pixels)
    # A light moved by hand gives what a file holding it gives the tool.
    bulb = {"type": "point", "position": [0.2, 0.4, 0.3], "intensity": 0.4, "range": 2.0}
    (tmp_path / "bulb.json").write_text(json.dumps({"lights": [bulb]}))
    expected = light_tool(gbuffer, tmp_path / "tool.exr", "--lights", tmp_path / "bulb.json")
    same_bits(dhdr.light(g, [bulb]).pixels, expected)
    same_bits(dhdr.light(g, {"lights": [bulb]}).pixels, expected)


def test_light_errors_name_what_is_wrong(gbuffer, tmp_path):
    g = dhdr.read_gbuffer(str(gbuffer))
    with pytest.raises(ValueError, match=r'light 0 \(point\): unknown key "colour"'):
        dhdr.light(g, [{"type": "point", "position": [0, 0, 0], "colour": [1, 0, 0]}])
    bad = run_tool("dhdr-light", gbuffer, "--lights", tmp_path / "none.json", "-o",
                   tmp_path / "x.exr", check=False)
    with pytest.raises(ValueError) as e:
        dhdr.light(g, str(tmp_path / "none.json"))
    assert str(e.value) == tool_error(bad)
    with pytest.raises(ValueError, match="ao must be"):
        dhdr.light(g, str(LIGHTS), ao="hbao")
    with pytest.raises(ValueError, match="shadow_samples: 0 is outside"):
        dhdr.light(g, str(LIGHTS), shadow_samples=0)
    # A colour image is no G-buffer: the tool's message.
    colour = write_exr(tmp_path / "c.exr", np.ones((8, 8, 4), np.float32), list("RGBA"))
    bad = run_tool("dhdr-light", colour, "--lights", LIGHTS, "-o", tmp_path / "x.exr",
                   check=False)
    with pytest.raises(RuntimeError) as e:
        dhdr.read_gbuffer(str(colour))
    assert str(e.value) == tool_error(bad)
    no_normals = dhdr.Image(g.pixels[..., :2].copy(), g.channels[:2])
    with pytest.raises(RuntimeError, match="N.X|channel"):
        dhdr.light(no_normals, str(LIGHTS))


def blender_passes(g):
    """Cycles' passes of the same frame, as Blender writes them (Z up), with the camera
    matrices in the header (tests/test_light_tools.cpp writes the same)."""
    c = g.channel
    covered = c("A") > 0
    cols = [np.full_like(c("A"), 0.1)] * 3 + [np.ones_like(c("A")),
            np.where(covered, c("Z"), 1e10),
            c("P.X"), -c("P.Z"), c("P.Y"), c("N.X"), -c("N.Z"), c("N.Y"),
            c("emission.R"), c("emission.G"), c("emission.B"),
            c("albedo.R"), c("albedo.G"), c("albedo.B"), c("roughness"), c("metallic")]
    names = ([f"ViewLayer.Combined.{x}" for x in "RGBA"] + ["ViewLayer.Depth.Z"] +
             [f"ViewLayer.Position.{x}" for x in "XYZ"] + [f"ViewLayer.Normal.{x}" for x in "XYZ"] +
             [f"ViewLayer.Emit.{x}" for x in "RGB"] + [f"ViewLayer.BaseColor.{x}" for x in "RGB"] +
             ["ViewLayer.Roughness.X", "ViewLayer.Metallic.X"])
    passes = dhdr.Image(np.stack(cols, axis=2), names)
    for m in ("worldToCamera", "worldToNDC"):
        passes.set_attribute(m, g.attributes[m])
    return passes


def test_blender_passes_equal_tool(gbuffer, tmp_path):
    passes = blender_passes(dhdr.read_gbuffer(str(gbuffer)))
    dhdr.write(str(tmp_path / "blender.exr"), passes, type="float")
    expected = light_tool(tmp_path / "blender.exr", tmp_path / "tool.exr", "--lights", LIGHTS,
                          "--channels", "blender", "--radiometric")
    read_back = dhdr.read_channels(str(tmp_path / "blender.exr"))
    mine = dhdr.light(dhdr.import_gbuffer(read_back, "blender"), str(LIGHTS), radiometric=True)
    same_bits(mine.pixels, expected)
    # In memory, without the file: the same G-buffer.
    same_bits(dhdr.light(dhdr.import_gbuffer(passes), str(LIGHTS), radiometric=True).pixels,
              expected)
    with pytest.raises(ValueError, match="Depth.Z"):
        dhdr.import_gbuffer(dhdr.Image(passes.pixels[..., :4].copy(), passes.channels[:4]))


def test_light_budget_equals_tool(gbuffer, tmp_path):
    """Twenty small sphere lights in the box: the shared budget (the default) and each light its
    own rays (light_budget=0) are dhdr-light's --light-budget, and differ."""
    rng = np.random.default_rng(7)
    spheres = [{"type": "sphere", "position": [float(v) for v in rng.uniform(0.1, 0.45, 3)],
                "radius": 0.02, "intensity": 0.05, "range": 1.0} for _ in range(20)]
    lights = tmp_path / "spheres.json"
    lights.write_text(json.dumps({"lights": spheres}))
    scene = str(TESTDATA / "cornell_box.gltf")
    g = dhdr.read_gbuffer(str(gbuffer))
    shared = dhdr.light(g, str(lights), scene=dhdr.Scene(scene), gi="direct")
    own = dhdr.light(g, str(lights), scene=dhdr.Scene(scene), gi="direct", light_budget=0)
    same_bits(shared.pixels, light_tool(gbuffer, tmp_path / "shared.exr", "--lights", lights,
                                        "--scene", scene, "--gi", "direct"))
    same_bits(own.pixels, light_tool(gbuffer, tmp_path / "own.exr", "--lights", lights,
                                     "--scene", scene, "--gi", "direct", "--light-budget", "0"))
    assert not np.array_equal(shared.pixels, own.pixels)
    with pytest.raises(ValueError, match=r"light_budget: -1 is outside \[0, 65536\]"):
        dhdr.light(g, str(lights), light_budget=-1)
