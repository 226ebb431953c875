#!/usr/bin/env python3
"""Cost of visibility in dhdr-light: wall time, shading time, peak memory and rays per second
at 1920x1080 on the Cornell box, for the scene's default lights and for 1,000 point lights,
unshadowed against hard shadows, soft shadows (the emissive panel) and ray-traced AO; and the
error of screen-space AO against ray-traced AO.

    python3 bench/shadows.py --bin build/apps [--size 1920x1080]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lights import TESTDATA, run, write_lights  # noqa: E402


def shade_seconds(err):
    return float(re.search(r"shade ([0-9.]+) ms", err).group(1)) / 1000.0


def rays(err):
    m = re.search(r"([0-9]+) shadow rays .* ([0-9]+) AO rays[^;]*; ([0-9.]+) M rays/s per thread", err)
    return (int(m.group(1)), int(m.group(2)), float(m.group(3))) if m else (0, 0, 0.0)


def mean_abs_ao(a, b):
    out = subprocess.run(["oiiotool", a, "--ch", "AO", b, "--ch", "AO", "--diff"],
                         capture_output=True, text=True).stdout
    return float(re.search(r"Mean error = ([0-9.eE+-]+)", out).group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", default="1920x1080")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="dhdr_shadows_")
    tool = lambda name: os.path.join(args.bin, name)
    scene = os.path.join(TESTDATA, "cornell_box.gltf")
    gbuf = os.path.join(work, "gbuf.exr")
    own = os.path.join(work, "own.lights.json")
    subprocess.run([tool("dhdr-gbuffer"), scene, "--size", args.size, "--lights-out", own, "-o", gbuf],
                   check=True)
    fill = os.path.join(TESTDATA, "cornell_box.fill.lights.json")
    many = os.path.join(work, "many.json")
    write_lights(many, 1000, 0.12, 1000)
    out = os.path.join(work, "out.exr")

    def light(lights, extra, output=out):
        # --gi direct: the visibility's cost, without the probes --gi auto bakes with --scene.
        cmd = [tool("dhdr-light"), gbuf, "--gi", "direct", "-v", "-o", output] + extra
        for f in lights:
            cmd += ["--lights", f]
        return run(cmd)

    print("dhdr-light visibility: Cornell box %s, %d cores" % (args.size, os.cpu_count()))
    print("%-44s %7s %7s %7s %11s %10s %9s" % ("run", "wall s", "shade s", "MiB", "shadow rays",
                                             "AO rays", "Mray/s/t"))
    default = [own, fill]
    runs = [
        ("default lights, no --scene", default, []),
        ("default lights, --scene --no-shadows", default, ["--scene", scene, "--no-shadows", "--emissive-lights", "off"]),
        ("default lights, hard shadows", default, ["--scene", scene, "--emissive-lights", "off"]),
        ("default + emissive panel, soft shadows (16)", default, ["--scene", scene]),
        ("default lights, hard shadows + --ao rt (16)", default, ["--scene", scene, "--emissive-lights", "off", "--ao", "rt"]),
        ("default lights, hard shadows + --ao ssao", default, ["--scene", scene, "--emissive-lights", "off", "--ao", "ssao"]),
        ("1,000 point lights, --no-shadows", [many], ["--scene", scene, "--no-shadows", "--emissive-lights", "off"]),
        ("1,000 point lights, hard shadows", [many], ["--scene", scene, "--emissive-lights", "off"]),
    ]
    shade = {}
    for name, lights, extra in runs:
        wall, rss, err = light(lights, extra)
        s = shade_seconds(err)
        shade[name] = (wall, s)
        sr, ar, rate = rays(err)
        print("%-44s %7.3f %7.3f %7.1f %11d %10d %9.2f" % (name, wall, s, rss, sr, ar, rate))
    ratio = lambda a, b: shade[a][1] / shade[b][1]
    print("hard shadows / unshadowed, default lights: shading %.2fx, wall %.2fx" % (
        ratio("default lights, hard shadows", "default lights, --scene --no-shadows"),
        shade["default lights, hard shadows"][0] / shade["default lights, --scene --no-shadows"][0]))
    print("hard shadows / unshadowed, 1,000 lights: shading %.2fx, wall %.2fx" % (
        ratio("1,000 point lights, hard shadows", "1,000 point lights, --no-shadows"),
        shade["1,000 point lights, hard shadows"][0] / shade["1,000 point lights, --no-shadows"][0]))
    print("--ao rt (16) adds %.2f s of shading" % (
        shade["default lights, hard shadows + --ao rt (16)"][1] - shade["default lights, hard shadows"][1]))

    # SSAO against ray-traced AO, at the same distance / radius.
    for d in ("0.1", "1"):
        rt, ss = os.path.join(work, "rt.exr"), os.path.join(work, "ss.exr")
        light(default, ["--scene", scene, "--ao", "rt", "--ao-samples", "64", "--ao-distance", d, "--aovs"], rt)
        light(default, ["--ao", "ssao", "--ao-distance", d, "--aovs"], ss)
        print("ssao vs rt (64 rays) AO at distance %s m: mean |difference| %.3f" % (d, mean_abs_ao(rt, ss)))
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
