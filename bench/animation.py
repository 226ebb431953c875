#!/usr/bin/env python3
"""Animation at 1920x1080 (issue 24): dhdr-gbuffer on testdata/cornell_animated.gltf, 48 frames
in one --frames call (scene loaded once, moving meshes refitted, motion layer written) against
one static frame of the same scene (cornell_box.gltf, no motion layer) and one --frame of the
animated one: wall time per frame and peak memory.

    python3 bench/animation.py --bin build/apps [--size 1920x1080] [--frames 48] [--runs 3] [--shot]

--shot times the issue's own example instead: testdata/shot.gltf (the Cornell box with a turning
and a hopping block, a skinned arm, a camera move and a swinging spot; 1 s long) at --fps 48 so
that the 48 frames are all different poses, against the same file's rest pose rendered as a
static frame (no --frame: no posing, no motion layer).
"""
import argparse
import os
import shutil
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lights import TESTDATA, run  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--frames", type=int, default=48)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--shot", action="store_true", help="time testdata/shot.gltf at --fps 48")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="dhdr_anim_")
    gbuffer = os.path.join(args.bin, "dhdr-gbuffer")
    static = os.path.join(TESTDATA, "cornell_box.gltf")
    animated = os.path.join(TESTDATA, "cornell_animated.gltf")
    timing = []
    if args.shot:
        static = animated = os.path.join(TESTDATA, "shot.gltf")
        timing = ["--fps", "48"]
    rows = []
    try:
        def median(cmd):
            results = [run(cmd) for _ in range(args.runs)]
            return statistics.median(r[0] for r in results), max(r[1] for r in results)

        wall, rss = median([gbuffer, static, "--size", args.size, "-o", os.path.join(work, "s.exr")])
        rows.append(("static frame (%s%s)" % (os.path.basename(static), ", rest pose" if args.shot else ""), 1, wall, wall, rss))
        wall, rss = median([gbuffer, animated, "--size", args.size, "--frame", "24"] + timing + ["-o",
                            os.path.join(work, "a.exr")])
        rows.append(("one animated frame (--frame 24)", 1, wall, wall, rss))
        wall, rss = median([gbuffer, animated, "--size", args.size, "--frames",
                            "1-%d" % args.frames] + timing + ["-o", os.path.join(work, "f.####.exr")])
        rows.append(("--frames 1-%d" % args.frames, args.frames, wall, wall / args.frames, rss))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("| run | frames | wall s | s / frame | × static frame | peak MiB |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, frames, wall, per, rss in rows:
        print("| %s | %d | %.2f | %.3f | %.2f | %.0f |" % (name, frames, wall, per, per / rows[0][3], rss))


if __name__ == "__main__":
    main()
