#!/usr/bin/env python3
"""Image-based lighting: dhdr-ibl on a 2048x1024 HDR (a sky with a sun made with oiiotool), and
dhdr-light at 1920x1080 on the bundled spheres with a ground plane under that environment,
--ao rt and --env-samples 16: wall time and peak memory.

    python3 bench/ibl.py --bin build/apps
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lights import TESTDATA, run  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="dhdr_ibl_")
    tool = lambda name: os.path.join(args.bin, name)
    sky = os.path.join(work, "sky.exr")
    subprocess.run(["oiiotool", "--pattern", "fill:top=0.35,0.55,1.0:bottom=0.9,0.9,0.95", "2048x512", "3",
                    "--pattern", "fill:top=0.25,0.22,0.2:bottom=0.12,0.1,0.09", "2048x512", "3",
                    "--mosaic", "1x2", "--box:color=30000,28000,24000:fill=1", "1530,230,1542,242",
                    "-d", "float", "-o", sky], check=True)
    print("IBL: %d cores" % os.cpu_count())
    for i in range(3):
        wall, rss, err = run([tool("dhdr-ibl"), sky, "-o", os.path.join(work, "sky.ibl.exr"), "-v"])
        print("dhdr-ibl 2048x1024 (6 levels from 256 wide, 128 samples, DFG 128^2 x 1024): "
              "%.3f s, %.0f MiB  [%s]" % (wall, rss, err.strip().splitlines()[-1]))
    with open(os.path.join(work, "sky.lights.json"), "w") as f:
        f.write('{"lights": [{"type": "environment", "image": "sky.ibl.exr"}]}\n')
    scene = os.path.join(TESTDATA, "spheres.gltf")
    gbuf = os.path.join(work, "g.exr")
    subprocess.run([tool("dhdr-gbuffer"), scene, "--size", "1920x1080", "--ground-plane", "-o", gbuf, "-q"],
                   check=True)
    base = [tool("dhdr-light"), gbuf, "--lights", os.path.join(work, "sky.lights.json"), "-v",
            "-o", os.path.join(work, "out.exr")]
    walls = []
    for name, extra in [("environment, no --scene", []),
                        ("+ --scene --ao rt --env-samples 16", ["--scene", scene, "--ao", "rt", "--env-samples", "16"]),
                        ("+ --plate env", ["--scene", scene, "--ao", "rt", "--env-samples", "16", "--plate", "env"])]:
        wall, rss, err = run(base + extra)
        walls.append(wall)
        total = [l for l in err.splitlines() if "total" in l][-1]
        print("dhdr-light 1920x1080 %-38s %.3f s, %.0f MiB  [%s]" % (name, wall, rss, total.split(": ", 1)[1]))
    # Issue 22's bound: the frame with --scene in at most 2x the environment-only frame's time.
    print("--scene against the environment only: %.2fx" % (walls[1] / walls[0]))
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
