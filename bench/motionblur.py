#!/usr/bin/python3
"""dhdr-motionblur against dhdr-bloom on the same frame: wall seconds (median of --repeat) and
peak memory. The frame is generated: rings of bright surfaces at several depths moving in
several directions (up to --speed pixels a frame) over a static background, written as an HDR
EXR and a G-buffer with Z and motion.X..W (Blender's convention).

    /usr/bin/python3 bench/motionblur.py --bin build/apps [--sizes 1920x1080] [--samples 8]
    /usr/bin/python3 bench/motionblur.py --bin build/apps --sizes 15360x8640 --repeat 1   (16K)
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import OpenImageIO as oiio



def measure(cmd):
    """Wall seconds and peak RSS (MiB) of one run, measured by /usr/bin/time: this process
    holds the generated frame, which a forked child's own ru_maxrss would count."""
    start = time.perf_counter()
    p = subprocess.run(["/usr/bin/time", "-f", "%M"] + cmd, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if p.returncode != 0:
        sys.exit("bench: %s failed:\n%s" % (" ".join(cmd), p.stderr))
    return wall, int(p.stderr.strip().splitlines()[-1]) / 1024.0


def write_frame(hdr, gbuf, w, h, speed):
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    r = np.hypot(x - 0.5 * w, y - 0.5 * h) / (0.02 * h)
    ring = r.astype(np.int32)
    moving = ring % 2 == 1
    c = np.where(moving, 4.0 + (ring % 7), 0.2 + 0.01 * (x % 7)).astype(np.float32)
    rgba = np.stack([c, 0.7 * c, 0.4 * c, np.ones_like(c)], axis=-1)
    u = np.where(moving, speed * ((ring % 3) - 1 + (ring == 1)), 0.0).astype(np.float32)
    v = np.where(moving, 0.5 * speed, 0.0).astype(np.float32)
    z = np.where(moving, 2.0 + ring, 50.0).astype(np.float32)
    g = np.stack([z, -u, -v, -u, -v], axis=-1)
    for path, pixels, names in [(hdr, rgba, ["R", "G", "B", "A"]),
                                (gbuf, g, ["Z", "motion.X", "motion.Y", "motion.Z", "motion.W"])]:
        spec = oiio.ImageSpec(w, h, len(names), "float")
        spec.channelnames = names
        spec.attribute("compression", "zip")
        out = oiio.ImageOutput.create(path)
        out.open(path, spec)
        out.write_image(pixels)
        out.close()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--sizes", default="1920x1080")
    ap.add_argument("--samples", type=int, default=8)
    ap.add_argument("--speed", type=float, default=24.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    tool = lambda name: os.path.join(args.bin, name)
    work = tempfile.mkdtemp(prefix="dhdr_mb_")
    print("dhdr-motionblur vs dhdr-bloom: %d cores, median of %d" % (os.cpu_count(), args.repeat))
    print("%-12s %-44s %8s %8s %10s" % ("size", "run", "wall s", "best s", "peak MiB"))
    for size in args.sizes.split(","):
        w, h = (int(n) for n in size.split("x"))
        hdr, gbuf = os.path.join(work, "f.exr"), os.path.join(work, "f.gbuf.exr")
        write_frame(hdr, gbuf, w, h, args.speed * h / 1080.0)
        runs = [("dhdr-motionblur --samples %d" % args.samples,
                 [tool("dhdr-motionblur"), hdr, "--gbuffer", gbuf, "--samples", str(args.samples),
                  "-o", os.path.join(work, "mb.exr")]),
                ("dhdr-bloom", [tool("dhdr-bloom"), hdr, "-o", os.path.join(work, "bloom.exr")])]
        for name, cmd in runs:
            walls, peak = [], 0.0
            for _ in range(args.repeat):
                wall, rss = measure(cmd)
                walls.append(wall)
                peak = max(peak, rss)
            print("%-12s %-44s %8.2f %8.2f %10.0f" % (size, name, statistics.median(walls), min(walls), peak))
        for f in os.listdir(work):
            os.remove(os.path.join(work, f))
    os.rmdir(work)


if __name__ == "__main__":
    main()
