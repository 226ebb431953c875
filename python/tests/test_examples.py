"""The three examples of docs/python.md, run as a user runs them, against the tools."""
import json
import sys

import numpy as np

import dhdr
from conftest import HERE, LIGHTS, hdr_frame, read_file, run_tool, write_exr
from test_light import blender_passes
from test_tonemap import same_bits

sys.path.insert(0, str(HERE.parent / "examples"))
import adapt_sequence  # noqa: E402
import blender_composite  # noqa: E402
import relight_contact_sheet  # noqa: E402


def test_relight_contact_sheet(gbuffer, tmp_path):
    relight_contact_sheet.main(str(gbuffer), str(LIGHTS), str(tmp_path / "sheet.png"))
    sheet = read_file(tmp_path / "sheet.png")
    assert sheet.shape == (2 * 48, 5 * 64, 4)
    cells = [sheet[r * 48:(r + 1) * 48, c * 64:(c + 1) * 64] for r in range(2) for c in range(5)]
    assert len({c.tobytes() for c in cells}) == 10  # ten different lightings
    # The first cell is what the tools make of the first position.
    lights = dhdr.read_lights(str(LIGHTS))
    bulb = next(l for l in lights if l["type"] == "point")
    bulb["position"][0] += 0.15
    (tmp_path / "first.json").write_text(json.dumps({"lights": lights}))
    run_tool("dhdr-light", gbuffer, "--lights", tmp_path / "first.json", "--type", "float",
             "-o", tmp_path / "first.exr")
    run_tool("dhdr-tonemap", tmp_path / "first.exr", "-o", tmp_path / "first.png")
    same_bits(cells[0], read_file(tmp_path / "first.png"))


def test_adapt_sequence(tmp_path, capsys):
    for i, scale in enumerate([1.0, 6.0, 6.0, 0.5], start=1):
        write_exr(tmp_path / f"shot.{i:04d}.exr",
                  hdr_frame(seed=i) * np.array([scale, scale, scale, 1], np.float32), list("RGBA"))
    adapt_sequence.main(str(tmp_path / "shot.####.exr"), 1, 4, str(tmp_path / "py.####.png"), 30)
    assert "adapted" in capsys.readouterr().out
    run_tool("dhdr-tonemap", tmp_path / "shot.####.exr", "--adapt", "--fps", "30",
             "-o", tmp_path / "tool.####.png")
    for i in range(1, 5):
        same_bits(read_file(tmp_path / f"py.{i:04d}.png"),
                  read_file(tmp_path / f"tool.{i:04d}.png"))


def test_blender_composite(gbuffer, tmp_path):
    passes = blender_passes(dhdr.read_gbuffer(str(gbuffer)))
    dhdr.write(str(tmp_path / "passes.exr"), passes, type="float")
    plate = write_exr(tmp_path / "plate.exr", hdr_frame(seed=9, width=64, height=48), list("RGBA"))
    lit, frame = blender_composite.main(str(tmp_path / "passes.exr"), str(LIGHTS), str(plate),
                                        str(tmp_path / "out.png"))
    # The tools on the same passes, with the lights the example made.
    lights = dhdr.read_lights(str(LIGHTS))
    for light in lights:
        if light["type"] != "ambient":
            light["color"] = [1.0, 0.8, 0.6]
    (tmp_path / "warm.json").write_text(json.dumps({"lights": lights}))
    args = [tmp_path / "passes.exr", "--channels", "blender", "--lights", tmp_path / "warm.json",
            "--radiometric", "--type", "float"]
    run_tool("dhdr-light", *args, "-o", tmp_path / "lit.exr")
    same_bits(lit.pixels, read_file(tmp_path / "lit.exr"))
    run_tool("dhdr-light", *args, "--plate", plate, "-o", tmp_path / "comp.exr")
    same_bits(frame.pixels, read_file(tmp_path / "comp.exr"))  # numpy's "over" is the tool's
    run_tool("dhdr-tonemap", tmp_path / "comp.exr", "-o", tmp_path / "tool.png")
    same_bits(read_file(tmp_path / "out.png"), read_file(tmp_path / "tool.png"))
