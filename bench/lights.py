#!/usr/bin/env python3
"""Light-count scaling of dhdr-light: wall time and peak memory at 1920x1080 on the Cornell box
for N random point lights, culled and (up to --brute-max) brute force.

The lights are spread uniformly through the scene's bounds with one range for all, chosen so
that an average covered pixel lies within range of about --reach lights at every N: the range
is calibrated once (measured with dhdr-light -v) and scaled as N^(-1/3).

    python3 bench/lights.py --bin build/apps [--counts 1000,10000,100000] [--brute-max 10000]
"""
import argparse
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
TESTDATA = os.path.join(HERE, "..", "testdata")
# The Cornell box's bounds (testdata/make_cornell_box.py), metres.
BOUNDS = ((0.0, 0.0, 0.0), (0.556, 0.5488, 0.5592))


def write_lights(path, n, light_range, seed):
    rng = random.Random(seed)
    (x0, y0, z0), (x1, y1, z1) = BOUNDS
    lights = []
    for _ in range(n):
        lights.append({
            "type": "point",
            "position": [round(rng.uniform(x0, x1), 5), round(rng.uniform(y0, y1), 5),
                         round(rng.uniform(z0, z1), 5)],
            "color": [round(rng.uniform(0.3, 1.0), 3) for _ in range(3)],
            "intensity": round(rng.uniform(0.5, 1.0) * 20.0 / n, 8),
            "range": round(light_range, 6),
        })
    with open(path, "w") as f:
        json.dump({"lights": lights}, f)


TIME = "/usr/bin/time"  # Debian's `time`


def run(cmd):
    """Runs `cmd`: its wall time (s), peak memory (MiB) and stderr. A child started by this
    process would report this process's peak memory when larger (Linux keeps the high-water
    mark across fork and exec), so where GNU time is installed it starts the tool and reports
    the tool's own peak."""
    timed = os.path.exists(TIME)
    full = [TIME, "-f", "dhdr-bench-peak-kib %M"] + cmd if timed else cmd
    start = time.perf_counter()
    proc = subprocess.Popen(full, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    err = proc.stderr.read().decode()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    peak = usage.ru_maxrss
    if timed:
        lines = err.rstrip("\n").split("\n")
        if lines and lines[-1].startswith("dhdr-bench-peak-kib "):
            peak = int(lines[-1].split()[1])
            err = "\n".join(lines[:-1]) + ("\n" if len(lines) > 1 else "")
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("bench: %s failed:\n%s" % (" ".join(cmd), err))
    return wall, peak / 1024.0, err


def per_pixel(err):
    m = re.search(r"per covered pixel ([0-9.]+) considered, ([0-9.]+) within range", err)
    s = re.search(r"shade ([0-9.]+) ms", err)
    return float(m.group(1)), float(m.group(2)), float(s.group(1)) / 1000.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--counts", default="1000,10000,100000")
    ap.add_argument("--brute-max", type=int, default=10000)
    ap.add_argument("--reach", type=float, default=20.0)
    args = ap.parse_args()

    work = tempfile.mkdtemp(prefix="dhdr_lights_")
    tool = lambda name: os.path.join(args.bin, name)
    gbuf = os.path.join(work, "gbuf.exr")
    subprocess.run([tool("dhdr-gbuffer"), os.path.join(TESTDATA, "cornell_box.gltf"), "--size", args.size,
                    "-o", gbuf], check=True)
    light = lambda lights, extra: [tool("dhdr-light"), gbuf, "--lights", lights, "-v",
                                   "-o", os.path.join(work, "out.exr")] + extra

    # Calibrate the range at the first count, then scale it as N^(-1/3).
    counts = [int(c) for c in args.counts.split(",")]
    (x0, y0, z0), (x1, y1, z1) = BOUNDS
    volume = (x1 - x0) * (y1 - y0) * (z1 - z0)
    base = counts[0]
    r = (args.reach * volume / (base * 4.0 / 3.0 * 3.14159265)) ** (1.0 / 3.0)
    for _ in range(3):
        calib = os.path.join(work, "calib.json")
        write_lights(calib, base, r, 1)
        _, reached, _ = per_pixel(run(light(calib, []))[2])
        r *= (args.reach / reached) ** (1.0 / 3.0)

    print("dhdr-light scaling: Cornell box %s, %d cores, point lights reaching ~%g lights per pixel"
          % (args.size, os.cpu_count(), args.reach))
    print("%8s %8s %8s %9s | %8s %8s %8s | %8s %8s %8s | %7s" % (
        "lights", "range", "reach", "consider", "wall s", "shade s", "MiB", "brute s", "shade s", "MiB",
        "shade x"))
    first = None
    for n in counts:
        path = os.path.join(work, "lights_%d.json" % n)
        rn = r * (base / n) ** (1.0 / 3.0)
        write_lights(path, n, rn, n)
        wall, rss, err = run(light(path, []))
        considered, reached, shade = per_pixel(err)
        first = first or wall
        row = "%8d %8.4f %8.2f %9.2f | %8.3f %8.3f %8.1f |" % (n, rn, reached, considered, wall, shade, rss)
        if n <= args.brute_max:
            bwall, brss, berr = run(light(path, ["--brute-force"]))
            _, _, bshade = per_pixel(berr)
            row += " %8.3f %8.3f %8.1f | %7.1f" % (bwall, bshade, brss, bshade / shade)
        else:
            row += " %8s %8s %8s | %7s" % ("-", "-", "-", "-")
        print(row)
    print("time(%d) / time(%d) = %.2f (whole process)" % (counts[-1], counts[0], wall / first))
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
