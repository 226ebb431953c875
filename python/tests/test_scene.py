"""Scenes, render_gbuffer and light(scene=...) against dhdr-gbuffer and dhdr-light."""
import numpy as np
import pytest

import dhdr
from conftest import (LIGHTS, TESTDATA, range_error_is_the_tools, read_channels, read_file,
                      run_tool, tool_error)
from test_tonemap import same_bits

CORNELL = str(TESTDATA / "cornell_box.gltf")


@pytest.fixture(scope="module")
def cornell():
    return dhdr.Scene(CORNELL)


def test_scene_information_is_the_tools(cornell):
    assert cornell.info() == run_tool("dhdr-gbuffer", CORNELL, "--info").stdout
    assert cornell.cameras[0]["name"] and "yfov_degrees" in cornell.cameras[0]
    assert cornell.objects and cornell.materials
    lo, hi = cornell.bounds
    assert all(a < b for a, b in zip(lo, hi))
    assert isinstance(cornell.lights, list)
    with pytest.raises(RuntimeError, match="nothing.gltf"):
        dhdr.Scene(str(TESTDATA / "nothing.gltf"))


def test_materials_are_those_in_use_as_dicts(cornell):
    """--info's materials: Assimp's default one, which no mesh uses, is not among them."""
    by_name = {m["name"]: m for m in cornell.materials}
    assert sorted(by_name) == ["green", "light", "red", "white"]
    white, light = by_name["white"], by_name["light"]
    assert white["base_color"] == pytest.approx((0.725, 0.71, 0.68))
    assert (white["metallic"], white["alpha_mode"]) == (0.0, "opaque")
    assert white["roughness"] == pytest.approx(0.9)
    assert white["textures"] == {} and white["extensions"] == []
    assert (white["clearcoat"], white["clearcoat_roughness"]) == (0.0, 0.0)
    assert (white["sheen_color"], white["sheen_roughness"]) == ((0.0, 0.0, 0.0), 0.0)
    # The ceiling panel's KHR_materials_emissive_strength is read: in its emission, not unread.
    assert light["extensions"] == ["KHR_materials_emissive_strength"]
    assert light["extensions_not_read"] == []
    assert max(light["emission"]) > 1.0


@pytest.mark.parametrize("args, kwargs", [
    ([], {}),
    (["--lookat", "0.3,0.3,-0.9,0.28,0.27,0.28", "--fov", "50"],
     dict(lookat=(0.3, 0.3, -0.9, 0.28, 0.27, 0.28), fov=50)),
    (["--frame-all"], dict(frame_all=True)),
])
def test_render_gbuffer_equals_tool(cornell, tmp_path, args, kwargs):
    run_tool("dhdr-gbuffer", CORNELL, "--size", "48x32", *args, "-o", tmp_path / "tool.exr")
    g = dhdr.render_gbuffer(cornell, size=(48, 32), **kwargs)
    assert g.channels[:2] == ["A", "Z"] and g["N.X"].shape == (32, 48)
    dhdr.write_gbuffer(str(tmp_path / "py.exr"), g)
    tool, mine = dhdr.read_gbuffer(str(tmp_path / "tool.exr")), dhdr.read_gbuffer(
        str(tmp_path / "py.exr"))
    assert tool.channels == mine.channels
    same_bits(mine.pixels, tool.pixels)
    for key in ["worldToCamera", "worldToNDC", "dhdr:sceneSHA1"]:
        assert mine.attributes[key] == tool.attributes[key]


def test_camera_errors_are_the_tools(cornell, tmp_path):
    bad = run_tool("dhdr-gbuffer", CORNELL, "--camera", "Nope", "-o", tmp_path / "x.exr",
                   check=False)
    with pytest.raises(ValueError) as e:
        dhdr.render_gbuffer(cornell, camera="Nope", size=(8, 8))
    assert str(e.value) == tool_error(bad)
    with pytest.raises(ValueError, match="max_layers: 0 is outside"):
        dhdr.render_gbuffer(cornell, deep=True, max_layers=0)
    with pytest.raises(ValueError, match="6 or 9 numbers"):
        dhdr.render_gbuffer(cornell, lookat=(0, 0, 1))
    with pytest.raises(ValueError, match="texture_filter must be bilinear, trilinear or "
                                         "anisotropic, got 'ewa'"):
        dhdr.render_gbuffer(cornell, size=(8, 8), texture_filter="ewa")
    for choice in ("bilinear", "trilinear", "anisotropic"):
        dhdr.render_gbuffer(cornell, size=(8, 8), texture_filter=choice)
    for fov in (180, -1):
        range_error_is_the_tools(lambda: dhdr.render_gbuffer(cornell, size=(8, 8), fov=fov),
                                 "dhdr-gbuffer", "--fov", fov, CORNELL, "-o", tmp_path / "x.exr")


def test_light_with_scene_equals_tool(cornell, gbuffer, tmp_path):
    g = dhdr.read_gbuffer(str(gbuffer))
    run_tool("dhdr-light", gbuffer, "--scene", CORNELL, "--type", "float",
             "-o", tmp_path / "own.exr")
    same_bits(dhdr.light(g, scene=cornell).pixels, read_file(tmp_path / "own.exr"))
    # gi='auto': the probes baked for the frame, and with aovs their indirect light.
    channels = ["R", "G", "B", "A", "AO", "indirect.R", "indirect.G", "indirect.B", "specular.R",
                "specular.G", "specular.B", "Z", "N.X", "N.Y", "N.Z"]
    run_tool("dhdr-light", gbuffer, "--scene", CORNELL, "--lights", LIGHTS, "--ao", "rt",
             "--ao-distance", "0.3", "--aovs", "--emissive-lights", "off", "--type", "float",
             "-o", tmp_path / "rt.exr")
    mine = dhdr.light(g, str(LIGHTS), scene=cornell, ao="rt", ao_distance=0.3, aovs=True,
                      emissive_lights=False)
    assert mine.channels == channels
    same_bits(mine.pixels, read_channels(tmp_path / "rt.exr", channels))
    unshadowed = dhdr.light(g, str(LIGHTS), scene=cornell, shadows=False,
                            emissive_lights=False, env_samples=0)
    assert not np.array_equal(unshadowed.pixels, mine.pixels[..., :4])
    with pytest.raises(ValueError, match="give scene="):
        dhdr.light(g, str(LIGHTS), ao="rt")
    with pytest.raises(ValueError, match="no lights"):
        dhdr.light(g)


def test_path_tracer_equals_tool(cornell, gbuffer, tmp_path):
    run_tool("dhdr-light", gbuffer, "--scene", CORNELL, "--gi", "path", "--spp", "2",
             "--path-bounces", "1", "--type", "float", "-o", tmp_path / "path.exr")
    mine = dhdr.light(dhdr.read_gbuffer(str(gbuffer)), scene=cornell, gi="path", spp=2,
                      path_bounces=1)
    same_bits(mine.pixels, read_file(tmp_path / "path.exr"))
    with pytest.raises(ValueError, match="give scene="):
        dhdr.light(dhdr.read_gbuffer(str(gbuffer)), str(LIGHTS), gi="path")
    with pytest.raises(ValueError, match="are for gi='path'"):
        dhdr.light(dhdr.read_gbuffer(str(gbuffer)), str(LIGHTS), spp=4)


def test_sheen_is_read_and_has_its_channels(cornell, tmp_path):
    """KHR_materials_sheen (testdata/make_sheen_spheres.py): its factors in Scene.materials, its
    channels in the G-buffer render_gbuffer gives (and the tool), none in a scene without."""
    import subprocess
    import sys
    subprocess.run([sys.executable, str(TESTDATA / "make_sheen_spheres.py"), str(tmp_path)],
                   check=True)
    path = str(tmp_path / "sheen_spheres.gltf")
    scene = dhdr.Scene(path)
    by_name = {m["name"]: m for m in scene.materials}
    assert by_name["sheen_1"]["sheen_color"] == pytest.approx((0.25, 0.25, 0.25))
    assert by_name["sheen_1"]["sheen_roughness"] == pytest.approx(0.5)
    assert by_name["sheen_5"]["sheen_roughness"] == pytest.approx(0.1)
    assert by_name["sheen_1"]["extensions_not_read"] == []
    g = dhdr.render_gbuffer(scene, size=(64, 32))
    assert ["sheen.R", "sheen.G", "sheen.B", "sheenRoughness"] == [
        c for c in g.channels if c.startswith("sheen")]
    run_tool("dhdr-gbuffer", path, "--size", "64x32", "-o", tmp_path / "tool.exr")
    dhdr.write_gbuffer(str(tmp_path / "py.exr"), g)
    assert dhdr.read_gbuffer(str(tmp_path / "tool.exr")).channels == dhdr.read_gbuffer(
        str(tmp_path / "py.exr")).channels
    assert not [c for c in dhdr.render_gbuffer(cornell, size=(8, 8)).channels if "sheen" in c]


def test_transmission_is_read_and_lit_as_the_tool(tmp_path):
    """KHR_materials_transmission (testdata/make_cornell_transmission.py): the factor in
    Scene.materials, render_gbuffer deep with its channel, and light() the tool's bits."""
    import subprocess
    import sys
    subprocess.run([sys.executable, str(TESTDATA / "make_cornell_transmission.py"),
                    str(tmp_path)], check=True)
    path = str(tmp_path / "cornell_transmission.gltf")
    glass = {m["name"]: m for m in dhdr.Scene(path).materials}["glass"]
    assert glass["transmission"] == 1.0
    assert glass["attenuation_distance"] == float("inf")
    assert "KHR_materials_transmission" not in glass["extensions_not_read"]
    g = dhdr.render_gbuffer(dhdr.Scene(path), size=(48, 48), deep="auto")
    assert "transmission" in g.channels
    run_tool("dhdr-gbuffer", path, "--size", "48x48", "-o", tmp_path / "g.exr")
    run_tool("dhdr-light", tmp_path / "g.exr", "--lights", LIGHTS, "--gi", "direct", "--type",
             "float", "-o",
             tmp_path / "tool.exr")
    mine = dhdr.light(dhdr.read_gbuffer(str(tmp_path / "g.exr")), str(LIGHTS), gi="direct")
    same_bits(mine, read_file(tmp_path / "tool.exr"))


def _textured_square(tmp_path, extensions):
    """A 2 x 2 square at z = 0 facing +Z, TEXCOORD_0 u along +X, its material "shiny" with
    `extensions`; images spec.png (RGBA, 4 x 1) and the file written beside it."""
    import base64
    import json
    import struct
    import OpenImageIO as oiio
    texels = np.array([[[255, 128, 64, 255], [64, 255, 128, 191], [128, 64, 255, 128],
                        [200, 200, 200, 32]]], dtype=np.uint8)
    spec = oiio.ImageSpec(4, 1, 4, "uint8")
    spec.attribute("oiio:UnassociatedAlpha", 1)
    out = oiio.ImageOutput.create(str(tmp_path / "spec.png"))
    assert out.open(str(tmp_path / "spec.png"), spec) and out.write_image(texels) and out.close()
    pos = [-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0]
    uv = [0, 1, 1, 1, 1, 0, 0, 0]
    data = struct.pack("12f", *pos) + struct.pack("8f", *uv) + struct.pack("6I", 0, 1, 2, 0, 2, 3)
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                        {"buffer": 0, "byteOffset": 80, "byteLength": 24}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [-1, -1, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                      {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1},
                                    "indices": 2, "material": 0}]}],
        "materials": [{"name": "shiny", "extensions": extensions,
                       "pbrMetallicRoughness": {"metallicFactor": 0.0}}],
        "images": [{"uri": "spec.png"}],
        "samplers": [{"magFilter": 9728}],
        "textures": [{"source": 0, "sampler": 0}],
        "nodes": [{"name": "square", "mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "extensionsUsed": list(extensions),
    }
    path = tmp_path / "square.gltf"
    path.write_text(json.dumps(doc))
    return str(path), texels


def test_specular_textures_are_listed_and_sampled(tmp_path):
    """KHR_materials_specular's textures (issue 44): in Scene.materials' textures by slot, and
    in render_gbuffer's specularWeight, the texel's A times specularFactor, as the tool's."""
    path, texels = _textured_square(tmp_path, {"KHR_materials_specular": {
        "specularFactor": 0.5, "specularTexture": {"index": 0},
        "specularColorTexture": {"index": 0}}})
    scene = dhdr.Scene(path)
    shiny = scene.materials[0]
    assert sorted(shiny["textures"]) == ["specular", "specular_color"]
    assert shiny["textures"]["specular"]["name"].endswith("spec.png")
    assert shiny["extensions_not_read"] == []
    assert not [w for w in scene.warnings if "not read" in w]
    g = dhdr.render_gbuffer(scene, size=(64, 64), lookat=(0, 0, 3, 0, 0, 0), fov=60)
    weight, x = g["specularWeight"][32], g["P.X"][32]
    for i, a in enumerate(texels[0, :, 3]):
        u = (x + 1) / 2 * 4 - i  # inside texel i: 0 < u < 1, away from its edges
        inside = (u > 0.2) & (u < 0.8) & (g["A"][32] == 1)
        assert inside.any()
        assert np.allclose(weight[inside], 0.5 * a / 255, rtol=1e-3)
    run_tool("dhdr-gbuffer", path, "--size", "64x64", "--lookat", "0,0,3,0,0,0", "--fov", "60",
             "-o", tmp_path / "tool.exr")
    dhdr.write_gbuffer(str(tmp_path / "py.exr"), g)
    same_bits(dhdr.read_gbuffer(str(tmp_path / "py.exr")).pixels,
              dhdr.read_gbuffer(str(tmp_path / "tool.exr")).pixels)
