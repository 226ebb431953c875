#!/usr/bin/env python3
"""Deep G-buffers at 1920x1080 on the Cornell box with a glass pane and a card with holes
(testdata/cornell_glass.gltf): dhdr-gbuffer deep against --flat (wall time, file size, peak
memory), and dhdr-light on each (shading time per shaded sample against the flat pass's per
covered pixel, peak memory against the samples), unshadowed and with --scene.

    python3 bench/deep.py --bin build/apps [--size 1920x1080]
"""
import argparse
import os
import re
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lights import TESTDATA, run  # noqa: E402


def shade_ms(err):
    return float(re.search(r"shade ([0-9.]+) ms", err).group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", default="1920x1080")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="dhdr_deep_")
    tool = lambda name: os.path.join(args.bin, name)
    scene = os.path.join(TESTDATA, "cornell_glass.gltf")
    lights = os.path.join(TESTDATA, "cornell_box.lights.json")
    print("Deep G-buffers, %s, %d cores" % (args.size, os.cpu_count()))
    files = {}
    for kind, extra in [("deep", []), ("flat", ["--flat"])]:
        path = os.path.join(work, kind + ".exr")
        wall, rss, err = run([tool("dhdr-gbuffer"), scene, "--size", args.size, "-o", path, "-v"] + extra)
        files[kind] = path
        line = [l for l in err.splitlines() if "deep:" in l or "trace" in l][-1]
        print("dhdr-gbuffer %-4s %.2f s, %.1f MiB file, %.0f MiB peak  [%s]"
              % (kind, wall, os.path.getsize(path) / 2**20, rss, line.split(": ", 1)[1]))
    for name, extra in [("lights file, no --scene", ["--lights", lights]),
                        ("--scene (shadows, emissive panel)",
                         ["--scene", scene, "--gi", "direct", "--lights", lights])]:
        out = os.path.join(work, "out.exr")
        wall_f, rss_f, err_f = run([tool("dhdr-light"), files["flat"], "-o", out, "-v"] + extra)
        covered = int(re.search(r"([0-9]+) covered pixels", err_f).group(1))
        wall_d, rss_d, err_d = run([tool("dhdr-light"), files["deep"], "-o", out, "-v"] + extra)
        m = re.search(r"deep: ([0-9]+) samples over ([0-9]+) covered pixels", err_d)
        samples = int(m.group(1))
        per_pixel = shade_ms(err_f) * 1e6 / covered
        per_sample = shade_ms(err_d) * 1e6 / samples
        print("dhdr-light %-34s flat: %.2f s, %.0f MiB, %.0f ns per covered pixel (%d); "
              "deep: %.2f s, %.0f MiB, %.0f ns per sample (%d samples); ratio %.2f"
              % (name, wall_f, rss_f, per_pixel, covered, wall_d, rss_d, per_sample, samples,
                 per_sample / per_pixel))
        print("    deep: %s" % [l for l in err_d.splitlines() if "total" in l][-1].split(": ", 1)[1])
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
