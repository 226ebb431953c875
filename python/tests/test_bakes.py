"""bake_ibl and bake_probes against dhdr-ibl and dhdr-probes, file for file, and their files
used by light()."""
import json

import numpy as np
import OpenImageIO as oiio
import pytest

import dhdr
from conftest import (LIGHTS, TESTDATA, range_error_is_the_tools, read_channels, read_file,
                      run_tool, write_exr)
from test_tonemap import same_bits

CORNELL = str(TESTDATA / "cornell_box.gltf")


def parts(path):
    """Every subimage's pixels (as stored) and header attributes but the software's."""
    inp = oiio.ImageInput.open(str(path))
    assert inp, oiio.geterror()
    out, i = [], 0
    while inp.seek_subimage(i, 0):
        spec = inp.spec()
        attrs = {a.name: a.value for a in spec.extra_attribs
                 if a.name not in ("Software", "DateTime")}
        out.append((inp.read_image(spec.format), attrs))
        i += 1
    inp.close()
    return out


def same_files(a, b):
    pa, pb = parts(a), parts(b)
    assert len(pa) == len(pb)
    for (pixels_a, attrs_a), (pixels_b, attrs_b) in zip(pa, pb):
        same_bits(pixels_a, pixels_b)
        assert attrs_a == attrs_b


@pytest.fixture(scope="module")
def sky(tmp_path_factory):
    """A 64x32 sky with a small bright sun."""
    rng = np.random.default_rng(5)
    env = (0.2 + 0.3 * rng.random((32, 64, 3))).astype(np.float32)
    env[6:8, 40:42] = 5000.0
    return write_exr(tmp_path_factory.mktemp("sky") / "sky.exr", env, list("RGB"))


def test_bake_ibl_equals_tool(sky, tmp_path):
    small = ["--levels", "3", "--base-width", "16", "--samples", "8", "--dfg-size", "8",
             "--dfg-samples", "16"]
    run_tool("dhdr-ibl", sky, *small, "-o", tmp_path / "tool.ibl.exr")
    info = dhdr.bake_ibl(str(sky), str(tmp_path / "py.ibl.exr"), levels=3, base_width=16,
                         samples=8, dfg_size=8, dfg_samples=16)
    assert (info["width"], info["height"]) == (64, 32) and info["sun"]["found"]
    same_files(tmp_path / "py.ibl.exr", tmp_path / "tool.ibl.exr")
    # The same sky held in memory.
    dhdr.bake_ibl(dhdr.read(str(sky)), str(tmp_path / "mem.ibl.exr"), levels=3, base_width=16,
                  samples=8, dfg_size=8, dfg_samples=16)
    same_files(tmp_path / "mem.ibl.exr", tmp_path / "tool.ibl.exr")
    with pytest.raises(ValueError, match="levels: 1 is outside"):
        dhdr.bake_ibl(str(sky), str(tmp_path / "x.exr"), levels=1)
    with pytest.raises(RuntimeError, match="twice as wide"):
        square = write_exr(tmp_path / "square.exr", np.ones((8, 8, 3), np.float32), list("RGB"))
        dhdr.bake_ibl(str(square), str(tmp_path / "x.exr"))


def test_baked_environment_lights_like_the_tool(sky, gbuffer, tmp_path):
    dhdr.bake_ibl(str(sky), str(tmp_path / "sky.ibl.exr"), levels=3, base_width=16, samples=8)
    lights = tmp_path / "env.json"
    lights.write_text(json.dumps({"lights": [{"type": "environment", "image": "sky.ibl.exr"}]}))
    run_tool("dhdr-light", gbuffer, "--lights", lights, "--type", "float", "-o", tmp_path / "t.exr")
    g = dhdr.read_gbuffer(str(gbuffer))
    expected = read_file(tmp_path / "t.exr")
    same_bits(dhdr.light(g, str(lights)).pixels, expected)
    # The same light as a dict: its image read and its sun split off as from the file.
    env = {"type": "environment", "image": str(tmp_path / "sky.ibl.exr")}
    same_bits(dhdr.light(g, [env]).pixels, expected)
    with pytest.raises(ValueError, match="environment image .*missing.exr"):
        dhdr.light(g, {"type": "environment", "image": str(tmp_path / "missing.exr")})


def test_bake_probes_equals_tool_and_lights(gbuffer, tmp_path):
    scene = dhdr.Scene(CORNELL)
    run_tool("dhdr-probes", CORNELL, "--grid", "2,2,2", "--rays", "32", "--bounces", "1",
             "-o", tmp_path / "tool.probes.exr")
    info = dhdr.bake_probes(scene, str(tmp_path / "py.probes.exr"), grid=(2, 2, 2), rays=32,
                            bounces=1)
    assert info["counts"] == (2, 2, 2) and info["active"] + info["relocated"] + info["off"] == 8
    same_files(tmp_path / "py.probes.exr", tmp_path / "tool.probes.exr")
    run_tool("dhdr-light", gbuffer, "--scene", CORNELL, "--probes", tmp_path / "tool.probes.exr",
             "--type", "float", "-o", tmp_path / "lit.exr")
    mine = dhdr.light(dhdr.read_gbuffer(str(gbuffer)), scene=scene,
                      probes=str(tmp_path / "py.probes.exr"))
    same_bits(mine.pixels, read_file(tmp_path / "lit.exr"))
    with pytest.raises(ValueError, match="rays: 1 is outside"):
        dhdr.bake_probes(scene, str(tmp_path / "x.exr"), rays=1)
    range_error_is_the_tools(lambda: dhdr.bake_probes(scene, str(tmp_path / "x.exr"), spacing=-1),
                             "dhdr-probes", "--spacing", -1, CORNELL, "-o", tmp_path / "x.exr")
    for grid in [(0, 2, 2), (2, 257, 2), (0, 0, 0)]:
        with pytest.raises(ValueError, match=r"grid: .* has a number outside \[1, 256\]"):
            dhdr.bake_probes(scene, str(tmp_path / "x.exr"), grid=grid)
        bad = run_tool("dhdr-probes", CORNELL, "--grid", ",".join(map(str, grid)), "-o",
                       tmp_path / "x.exr", check=False)
        assert bad.returncode == 2 and "[1, 256]" in bad.stderr


def test_probes_in_memory_light_as_the_tools_file(gbuffer, tmp_path):
    scene = dhdr.Scene(CORNELL)
    run_tool("dhdr-probes", CORNELL, "--grid", "2,2,2", "--rays", "32", "--bounces", "1",
             "-o", tmp_path / "tool.probes.exr")
    run_tool("dhdr-light", gbuffer, "--scene", CORNELL, "--probes", tmp_path / "tool.probes.exr",
             "--aovs", "--type", "float", "-o", tmp_path / "lit.exr")
    probes = dhdr.bake_probes(scene, grid=(2, 2, 2), rays=32, bounces=1)
    assert isinstance(probes, dhdr.Probes) and probes.counts == (2, 2, 2)
    assert probes.positions.shape == (8, 3) and probes.rays == 32 and probes.bounces == 1
    assert probes.info["active"] + probes.info["relocated"] + probes.info["off"] == 8
    assert not list(tmp_path.glob("*.probes.exr"))[1:]  # nothing written but the tool's
    g = dhdr.read_gbuffer(str(gbuffer))
    lit = dhdr.light(g, scene=scene, probes=probes, aovs=True)
    assert "indirect.R" in lit.channels
    same_bits(lit.pixels, read_channels(tmp_path / "lit.exr", lit.channels))
    # Written, the probes are the tool's file; read back, they light alike.
    probes.write(str(tmp_path / "py.probes.exr"))
    same_files(tmp_path / "py.probes.exr", tmp_path / "tool.probes.exr")
    read = dhdr.read_probes(str(tmp_path / "tool.probes.exr"))
    assert read.counts == probes.counts and read.origin == probes.origin
    same_bits(dhdr.light(g, scene=scene, probes=read, aovs=True).pixels, lit.pixels)
    with pytest.raises(ValueError, match="nothing.exr"):
        dhdr.read_probes(str(tmp_path / "nothing.exr"))
    with pytest.raises(TypeError, match="probes: expected"):
        dhdr.light(g, scene=scene, probes=3)
    with pytest.raises(ValueError, match="drop probes"):
        dhdr.light(g, scene=scene, probes=probes, gi="path")
