"""Animated scenes: Scene.animations and render_gbuffer(time=, frame=, fps=, animation=)
against dhdr-gbuffer --info, --frame, --time, --fps and --animation."""
import json
import pathlib
import re

import numpy as np
import OpenImageIO as oiio
import pytest

import dhdr
from conftest import TESTDATA, range_error_is_the_tools, read_channels, read_file, run_tool, tool_error
from test_tonemap import same_bits

ANIMATED = str(TESTDATA / "cornell_animated.gltf")
MOTION = ["motion.X", "motion.Y", "motion.Z", "motion.W"]


@pytest.fixture(scope="module")
def animated():
    return dhdr.Scene(ANIMATED)


def header(path):
    inp = oiio.ImageInput.open(str(path))
    assert inp, oiio.geterror()
    spec = inp.spec()
    inp.close()
    return spec


def test_animations_are_those_info_lists(animated):
    line = r"^    (\d+) '(.*)': (\S+) s \(keys from (\S+) to (\S+) s\), (\d+) channels$"
    listed = re.findall(line, run_tool("dhdr-gbuffer", ANIMATED, "--info").stdout, re.M)
    assert listed and len(listed) == len(animated.animations)
    for (index, name, duration, start, end, channels), a in zip(listed, animated.animations):
        assert a["name"] == name and a["channels"] == int(channels) and a["problem"] == ""
        for key, text in [("duration", duration), ("start", start), ("end", end)]:
            assert f"{a[key]:g}" == text
    assert dhdr.Scene(str(TESTDATA / "cornell_box.gltf")).animations == []


@pytest.mark.parametrize("args, kwargs", [
    (["--frame", "7"], dict(frame=7)),
    (["--time", "0.3125", "--fps", "30", "--animation", "all"],
     dict(time=0.3125, fps=30, animation="all")),
    (["--frame", "40", "--fps", "12", "--animation", "shot"],
     dict(frame=40, fps=12, animation=0)),  # past the end: the last pose, held
    ([], {}),  # frame 0 with its motion layer, as the tool renders an animated file
])
def test_animated_gbuffer_equals_tool(animated, tmp_path, args, kwargs):
    run_tool("dhdr-gbuffer", ANIMATED, "--size", "48x32", *args, "-o", tmp_path / "tool.exr")
    g = dhdr.render_gbuffer(animated, size=(48, 32), **kwargs)
    assert g.channels[-4:] == MOTION
    # The motion layer is float in the file: the array holds the tool's very bits.
    same_bits(np.ascontiguousarray(g.pixels[..., -4:]),
              read_channels(tmp_path / "tool.exr", MOTION))
    dhdr.write_gbuffer(str(tmp_path / "py.exr"), g)
    mine, tool = header(tmp_path / "py.exr"), header(tmp_path / "tool.exr")
    assert list(mine.channelnames) == list(tool.channelnames)
    assert [str(t) for t in mine.channelformats] == [str(t) for t in tool.channelformats]
    same_bits(read_file(tmp_path / "py.exr", oiio.FLOAT), read_file(tmp_path / "tool.exr",
                                                                   oiio.FLOAT))
    for key in ["dhdr:animationTime", "dhdr:fps", "dhdr:animation", "worldToCamera",
                "worldToNDC", "dhdr:sceneSHA1"]:
        assert mine.getattribute(key) == tool.getattribute(key), key
    assert g.attributes["dhdr:animationTime"] == tool.getattribute("dhdr:animationTime")


def test_moving_frames_differ_and_still_scenes_have_no_motion(animated):
    a = dhdr.render_gbuffer(animated, size=(24, 16), frame=3)
    b = dhdr.render_gbuffer(animated, size=(24, 16), time=3 / 24)
    same_bits(a.pixels, b.pixels)
    c = dhdr.render_gbuffer(animated, size=(24, 16), frame=12)
    assert not np.array_equal(a["P.X"], c["P.X"])
    still = dhdr.render_gbuffer(dhdr.Scene(str(TESTDATA / "cornell_box.gltf")), size=(24, 16))
    assert "motion.X" not in still.channels and "dhdr:animationTime" not in still.attributes
    with pytest.warns(RuntimeWarning, match="the scene has no animation"):
        dhdr.render_gbuffer(dhdr.Scene(str(TESTDATA / "cornell_box.gltf")), size=(8, 8), frame=2)


def test_animation_errors_are_the_tools(animated, tmp_path):
    bad = run_tool("dhdr-gbuffer", ANIMATED, "--animation", "jump", "-o", tmp_path / "x.exr",
                   check=False)
    assert bad.returncode == 1
    with pytest.raises(ValueError) as e:
        dhdr.render_gbuffer(animated, size=(8, 8), animation="jump")
    assert str(e.value) == tool_error(bad)
    assert "no animation 'jump' (the file has: 0 'shot')" in str(e.value)
    with pytest.raises(ValueError, match="no animation '3'"):
        dhdr.render_gbuffer(animated, size=(8, 8), animation=3)
    with pytest.raises(ValueError, match="exclude each other"):
        dhdr.render_gbuffer(animated, size=(8, 8), frame=1, time=0.5)
    with pytest.raises(ValueError, match="fps: 0 is outside"):
        dhdr.render_gbuffer(animated, size=(8, 8), fps=0)
    with pytest.raises(ValueError, match=r"frame: 1000000000 is outside \[-99999999, 999999999\]"):
        dhdr.render_gbuffer(animated, size=(8, 8), frame=10**9)
    with pytest.raises(ValueError, match="frame: 1000000000000 is outside"):
        dhdr.render_gbuffer(animated, size=(8, 8), frame=10**12)
    with pytest.raises(ValueError, match="time: inf is outside"):
        dhdr.render_gbuffer(animated, size=(8, 8), time=float("inf"))
    with pytest.raises(TypeError, match="animation: expected a name"):
        dhdr.render_gbuffer(animated, size=(8, 8), animation=1.5)


def test_an_unplayable_animation_is_the_files_error(tmp_path):
    # A LINEAR sampler turned CUBICSPLINE: one output a key where three are needed.
    doc = json.loads(pathlib.Path(ANIMATED).read_text())
    doc["animations"][0]["samplers"][0]["interpolation"] = "CUBICSPLINE"
    broken = tmp_path / "broken.gltf"
    broken.write_text(json.dumps(doc))
    bad = run_tool("dhdr-gbuffer", broken, "-o", tmp_path / "x.exr", check=False)
    scene = dhdr.Scene(str(broken))
    assert "cannot be played" not in scene.animations[0]["problem"]  # the problem, alone
    assert scene.animations[0]["problem"] and "sampler 0" in scene.animations[0]["problem"]
    with pytest.raises(RuntimeError) as e:
        dhdr.render_gbuffer(scene, size=(8, 8))
    assert str(e.value) == tool_error(bad) and "cannot be played" in str(e.value)


def expect_same_surfaces(still, moving):
    """A posed scene's G-buffer (`moving`, its rigid movers traced as Embree instances) against
    the same scene standing still (`still`, every triangle where it lies): the same surfaces,
    their points within both error bounds (the instance's barycentrics may differ in the last
    bits), the instance's bound the larger (it carries its transform's rounding). Which side of
    an edge a pixel's ray passes is decided in the last bits: a pixel or two may see another
    surface, and are left out."""
    a, b = np.asarray(still.pixels), np.asarray(moving.pixels)[..., :len(still.channels)]
    index = {c: i for i, c in enumerate(still.channels)}
    same = np.ones(a.shape[:2], bool)
    for name in ("A", "id.object", "id.material"):
        same &= a[..., index[name]] == b[..., index[name]]
    assert (~same).sum() <= 2
    bound = a[..., index["Perr"]] + b[..., index["Perr"]]
    covered = same & (a[..., index["A"]] > 0)
    assert covered.sum() > 100
    for name, i in index.items():
        x, y = a[..., i][same], b[..., i][same]
        on = covered[same]
        if name in ("P.X", "P.Y", "P.Z"):
            assert np.all(np.abs(x - y)[on] <= bound[covered]), name
        elif name == "Z":  # a unit row of the camera's matrix: at most √3 of P's bound
            assert np.all(np.abs(x - y)[on] <= 1.75 * bound[covered]), name
        elif name == "Perr":
            assert np.all(y[on] >= x[on]), name
        elif name.startswith("N"):  # normals at barycentrics a few ulps apart
            assert np.allclose(x, y, rtol=0, atol=1e-5), name
        else:
            same_bits(x, y)


def test_posed_scene_is_the_tools_frame(tmp_path):
    shot = str(TESTDATA / "shot.gltf")
    scene = dhdr.Scene(shot)
    run_tool("dhdr-gbuffer", shot, "--frame", "8", "--size", "32x24", "--lights-out",
             tmp_path / "lights.json", "-o", tmp_path / "g.exr")
    at8 = scene.posed(frame=8)
    assert at8.animations == [] and scene.animations
    # The spot swings: its lights at frame 8 are what --lights-out wrote, not the rest pose's.
    tool_lights = json.loads((tmp_path / "lights.json").read_text())["lights"]
    assert at8.lights == tool_lights and scene.lights != tool_lights
    assert scene.posed(time=8 / 24).lights == tool_lights
    # Standing still, it renders the frame's surfaces without a motion layer.
    still = dhdr.render_gbuffer(at8, size=(32, 24))
    moving = dhdr.render_gbuffer(scene, size=(32, 24), frame=8)
    assert still.channels == moving.channels[:-4]
    expect_same_surfaces(still, moving)
    # Lit against it, the frame is what light() poses the animated scene for by itself, within
    # what the instances' bits change; a shadow ray grazing an edge may go the other way, in a
    # value or two.
    lit_still, lit_moving = dhdr.light(moving, scene=at8).pixels, dhdr.light(moving, scene=scene).pixels
    assert np.count_nonzero(~np.isclose(lit_still, lit_moving, rtol=2**-16, atol=0)) <= 4
    with pytest.raises(ValueError, match="no animation 'walk'"):
        scene.posed(animation="walk")


def test_light_poses_the_scene_as_the_tool(animated, tmp_path):
    # dhdr-light --scene poses the scene at the moment the G-buffer records: the moving block's
    # shadow is where frame 20 puts it.
    run_tool("dhdr-gbuffer", ANIMATED, "--size", "48x32", "--frame", "20", "-o", tmp_path / "g.exr")
    # Direct light: probes baked over the posed scene (its block an instance) and over the scene
    # standing at that moment differ in their last bits.
    run_tool("dhdr-light", tmp_path / "g.exr", "--scene", ANIMATED, "--gi", "direct", "--type",
             "float", "-o", tmp_path / "lit.exr")
    g = dhdr.read_gbuffer(str(tmp_path / "g.exr"))
    lit = dhdr.light(g, scene=animated, gi="direct")
    same_bits(lit.pixels, read_file(tmp_path / "lit.exr"))
    # The scene standing at that moment lights it alike; its rest pose does not.
    same_bits(dhdr.light(g, scene=animated.posed(frame=20), gi="direct").pixels, lit.pixels)
    assert not np.array_equal(dhdr.light(g, scene=animated.posed(frame=0), gi="direct").pixels,
                              lit.pixels)
    # A G-buffer that records no moment is lit against the rest pose, with the tool's warning.
    bare = dhdr.Image(g.pixels, g.channels)
    for key in ["worldToCamera", "worldToNDC"]:
        bare.set_attribute(key, g.attributes[key])
    with pytest.warns(RuntimeWarning, match="records no animation time"):
        dhdr.light(bare, scene=animated)
    g.set_attribute("dhdr:animation", "3")
    with pytest.raises(ValueError, match="rendered with animation 3, which .* does not have"):
        dhdr.light(g, scene=animated)


@pytest.mark.parametrize("keyword, value", [("fps", 0), ("time", -2e9), ("frame", -10**8)])
def test_moment_range_errors_are_the_tools(animated, keyword, value, tmp_path):
    args = [ANIMATED, "-o", tmp_path / "x.exr"]
    range_error_is_the_tools(lambda: dhdr.render_gbuffer(animated, size=(8, 8), **{keyword: value}),
                             "dhdr-gbuffer", "--" + keyword, value, *args)
    range_error_is_the_tools(lambda: animated.posed(**{keyword: value}), "dhdr-probes",
                             "--" + keyword, value, *args)
