#!/usr/bin/env python3
"""Times the five dhdr stages on the Cornell box, per stage: wall seconds (median of
--repeat runs) and peak resident memory, at 1920x1080 and 3840x2160, next to the I/O floor
(oiiotool reading the same EXR and writing it out again).

    python3 bench/pipeline.py --bin build/apps [--sizes 1920x1080,3840x2160] [--repeat 3]
    python3 bench/pipeline.py --bin build/apps --sizes 15360x8640 --repeat 1 --no-floor
        (16K: the peak memory a farm node needs per stage; oiiotool's floor would take 14 GB)
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


def measure(cmd):
    """Wall seconds and peak RSS (MiB) of one run of cmd."""
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    err = proc.stderr.read().decode()
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        sys.exit("bench: %s failed (%d):\n%s" % (" ".join(cmd), proc.returncode, err))
    return wall, usage.ru_maxrss / 1024.0


def run(name, cmd, repeat, rows):
    walls, rss = [], 0.0
    for _ in range(repeat):
        wall, peak = measure(cmd)
        walls.append(wall)
        rss = max(rss, peak)
    rows.append((name, statistics.median(walls), min(walls), rss))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps", help="folder with the dhdr-* executables")
    ap.add_argument("--sizes", default="1920x1080,3840x2160")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--scene", default=os.path.join(TESTDATA, "cornell_box.gltf"))
    ap.add_argument("--lights", default=os.path.join(TESTDATA, "cornell_box.lights.json"))
    ap.add_argument("--keep", help="keep the outputs in this folder")
    ap.add_argument("--no-floor", action="store_true", help="skip the oiiotool I/O floor")
    args = ap.parse_args()

    tool = lambda name: os.path.join(args.bin, name)
    oiiotool = shutil.which("oiiotool")
    work = args.keep or tempfile.mkdtemp(prefix="dhdr_bench_")
    os.makedirs(work, exist_ok=True)
    print("dhdr pipeline benchmark: %s, %d cores, median of %d runs" %
          (os.path.basename(args.scene), os.cpu_count(), args.repeat))
    for size in args.sizes.split(","):
        f = lambda n: os.path.join(work, "%s.%s" % (size, n))
        rows = []
        run("dhdr-gbuffer", [tool("dhdr-gbuffer"), args.scene, "--size", size, "-o", f("gbuf.exr")],
            args.repeat, rows)
        run("dhdr-light", [tool("dhdr-light"), f("gbuf.exr"), "--lights", args.lights, "-o", f("hdr.exr")],
            args.repeat, rows)
        run("dhdr-aa", [tool("dhdr-aa"), f("hdr.exr"), "--gbuffer", f("gbuf.exr"), "-o", f("aa.exr")],
            args.repeat, rows)
        run("dhdr-bloom", [tool("dhdr-bloom"), f("aa.exr"), "-o", f("bloom.exr")], args.repeat, rows)
        run("dhdr-tonemap", [tool("dhdr-tonemap"), f("bloom.exr"), "-o", f("final.png")], args.repeat, rows)
        if oiiotool and not args.no_floor:
            run("floor: oiiotool gbuf.exr -> exr", [oiiotool, f("gbuf.exr"), "-o", f("floor.gbuf.exr")],
                args.repeat, rows)
            run("floor: oiiotool hdr.exr -> png", [oiiotool, f("bloom.exr"), "-d", "uint8", "-o", f("floor.png")],
                args.repeat, rows)
        print("\n%s" % size)
        print("%-34s %10s %10s %12s" % ("stage", "wall s", "best s", "peak MiB"))
        for name, wall, best, rss in rows:
            print("%-34s %10.3f %10.3f %12.1f" % (name, wall, best, rss))
    if not args.keep:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
