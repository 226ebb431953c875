#!/usr/bin/env python3
"""Light probes on the Cornell box: the dhdr-probes bake at 0.25 m and 0.1 m spacing (probes,
rays, seconds, peak memory), and dhdr-light at 1920x1080 with --scene, without and with the
probes.

    python3 bench/probes.py --bin build/apps
"""
import argparse
import os
import re
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lights import TESTDATA, run  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", default="1920x1080")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="dhdr_probes_")
    tool = lambda name: os.path.join(args.bin, name)
    scene = os.path.join(TESTDATA, "cornell_box.gltf")
    print("Light probes, %d cores" % os.cpu_count())
    for spacing in ("0.25", "0.1"):
        out = os.path.join(work, "p%s.exr" % spacing)
        wall, rss, err = run([tool("dhdr-probes"), scene, "--spacing", spacing, "-o", out, "-v"])
        summary = [l for l in err.splitlines() if "probes (" in l][-1].split(": ", 1)[1]
        times = [l for l in err.splitlines() if "bake" in l][-1].split(": ", 1)[1]
        print("dhdr-probes --spacing %-4s %.2f s, %.0f MiB  [%s; %s]" % (spacing, wall, rss, summary, times))
    gbuf = os.path.join(work, "g.exr")
    run([tool("dhdr-gbuffer"), scene, "--size", args.size, "-o", gbuf, "-q"])
    probes = ["--probes", os.path.join(work, "p0.1.exr")]
    lights = ["--lights", os.path.join(TESTDATA, "cornell_box.lights.json")]
    for name, extra in [("--lights", lights), ("--lights --probes (0.1 m)", lights + probes),
                        ("--scene --gi direct", ["--scene", scene, "--gi", "direct"]),
                        ("--scene (--gi auto: its own bake)", ["--scene", scene]),
                        ("--scene --probes (0.1 m)", ["--scene", scene] + probes)]:
        wall, rss, err = run([tool("dhdr-light"), gbuf, "-o", os.path.join(work, "o.exr"), "-v"] + extra)
        total = [l for l in err.splitlines() if "total" in l][-1].split(": ", 1)[1]
        print("dhdr-light %s %-26s %.2f s, %.0f MiB  [%s]" % (args.size, name, wall, rss, total))
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
