#!/usr/bin/env python3
"""dhdr-tonemap against the I/O floor: a 3840x2160 EXR to 8-bit PNG with reinhard,
reinhard-local and aces next to `oiiotool in.exr -d uint8 -o out.png` (same PNG zlib level,
OpenImageIO's default), and a 100-frame 1920x1080 sequence with --adapt on 1 and 2 threads next
to an `oiiotool --frames` loop doing plain conversion. Median of --repeat runs.

    python3 bench/tonemap.py --bin build/apps [--frames 100] [--repeat 3]
"""
import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
TESTDATA = os.path.join(HERE, "..", "testdata")


def timed(cmd, repeat):
    walls, rss = [], 0.0
    for _ in range(repeat):
        start = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        _, status, usage = os.wait4(proc.pid, 0)
        walls.append(time.perf_counter() - start)
        rss = max(rss, usage.ru_maxrss / 1024.0)
        if os.waitstatus_to_exitcode(status) != 0:
            sys.exit("bench: %s failed:\n%s" % (" ".join(cmd), proc.stderr.read().decode()))
    return statistics.median(walls), rss


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    oiiotool = shutil.which("oiiotool")
    if not oiiotool:
        sys.exit("bench: needs oiiotool (Debian's openimageio-tools)")
    tool = lambda name: os.path.join(args.bin, name)
    work = tempfile.mkdtemp(prefix="dhdr_tonemap_")
    f = lambda name: os.path.join(work, name)

    def frame(size, name):
        subprocess.run([tool("dhdr-gbuffer"), os.path.join(TESTDATA, "cornell_box.gltf"), "--size", size,
                        "-q", "-o", f("g.exr")], check=True)
        subprocess.run([tool("dhdr-light"), f("g.exr"), "--lights", os.path.join(TESTDATA, "cornell_box.lights.json"),
                        "--lights", os.path.join(TESTDATA, "cornell_box.fill.lights.json"),
                        "--background", "0.02,0.02,0.03", "-q", "-o", f(name)], check=True)

    frame("3840x2160", "4k.exr")
    print("dhdr-tonemap: %d cores, median of %d runs" % (os.cpu_count(), args.repeat))
    print("\n3840x2160 EXR -> 8-bit PNG")
    print("%-40s %9s %7s %9s" % ("", "wall s", "x floor", "peak MiB"))
    floor, rss = timed([oiiotool, f("4k.exr"), "-d", "uint8", "-o", f("floor.png")], args.repeat)
    print("%-40s %9.3f %7.2f %9.1f" % ("floor: oiiotool -d uint8", floor, 1.0, rss))
    for op in ("reinhard", "reinhard-local", "aces"):
        wall, rss = timed([tool("dhdr-tonemap"), f("4k.exr"), "--op", op, "-q", "-o", f(op + ".png")], args.repeat)
        print("%-40s %9.3f %7.2f %9.1f" % ("dhdr-tonemap --op " + op, wall, wall / floor, rss))

    frame("1920x1080", "hd.exr")
    os.makedirs(f("seq"))
    for i in range(1, args.frames + 1):
        os.link(f("hd.exr"), f("seq/in.%04d.exr" % i))
    print("\n%d-frame 1920x1080 sequence -> 8-bit PNG" % args.frames)
    print("%-40s %9s %9s %9s" % ("", "wall s", "frames/s", "peak MiB"))
    # oiiotool's "#" is a 4-digit frame number.
    loop, rss = timed([oiiotool, "--frames", "1-%d" % args.frames, f("seq/in.#.exr"), "-d", "uint8",
                       "-o", f("seq/o.#.png")], 1)
    print("%-40s %9.2f %9.1f %9.1f" % ("oiiotool --frames, plain conversion", loop, args.frames / loop, rss))
    walls = {}
    for threads in (1, 2):
        wall, rss = timed([tool("dhdr-tonemap"), f("seq/in.####.exr"), "--adapt", "--threads", str(threads),
                           "-q", "-o", f("seq/t.####.png")], 1)
        walls[threads] = wall
        print("%-40s %9.2f %9.1f %9.1f" % ("dhdr-tonemap --adapt --threads %d" % threads, wall,
                                            args.frames / wall, rss))
    print("speed-up 2 threads / 1: %.2f; against the oiiotool loop: %.2f" % (walls[1] / walls[2], loop / walls[2]))
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
