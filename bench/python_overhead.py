#!/usr/bin/env python3
"""The Python module's calls against the same library calls in C++ on a 1920x1080 frame
(issue 25: at most 5 % more). Renders the Cornell box's G-buffer with dhdr-gbuffer, times
light, tone_map, bloom and edge_aa in C++ (dhdr-bench-stages) and then through dhdr, each
making a new result as the return form does. The machine is shared, so the two alternate
for --rounds rounds of --runs calls each and the best time of each side is compared (load
only ever slows a call down).

    python3 bench/python_overhead.py --build build [--size 1920x1080] [--runs 5] [--rounds 3]
                                     [--threads N]
"""
import argparse
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent


def timed(runs, call):
    ms = []
    for _ in range(runs):
        t = time.perf_counter()
        call()
        ms.append((time.perf_counter() - t) * 1000.0)
    return min(ms), statistics.median(ms)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=str(ROOT / "build"))
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=0)
    args = ap.parse_args()
    build = pathlib.Path(args.build)
    sys.path.insert(0, str(build / "python"))
    import numpy as np
    import dhdr

    lights = ROOT / "testdata" / "cornell_box.lights.json"
    nt = args.threads
    with tempfile.TemporaryDirectory() as tmp:
        g_path = pathlib.Path(tmp) / "g.exr"
        subprocess.run([build / "apps" / "dhdr-gbuffer", ROOT / "testdata" / "cornell_box.gltf",
                        "--size", args.size, "-q", "-o", g_path], check=True)
        g = dhdr.read_gbuffer(str(g_path))
        hdr = dhdr.light(g, str(lights))
        n = g.channels.index("N.X")
        normal = np.ascontiguousarray(g.pixels[..., n:n + 3])
        depth = np.ascontiguousarray(g["Z"])
        calls = {
            "light": lambda: dhdr.light(g, str(lights), nthreads=nt),
            "tone_map": lambda: dhdr.tone_map(hdr, nthreads=nt),
            "bloom": lambda: dhdr.bloom(hdr, nthreads=nt),
            "edge_aa": lambda: dhdr.edge_aa(hdr, normal=normal, depth=depth, nthreads=nt),
        }
        cpp = {name: [] for name in calls}
        py = {name: [] for name in calls}
        for _ in range(args.rounds):
            out = subprocess.run([build / "dhdr-bench-stages", g_path, lights, str(args.runs),
                                  str(nt)], check=True, capture_output=True, text=True).stdout
            for line in out.splitlines():
                name, best, _median = line.split()
                cpp[name].append(float(best))
            for name, call in calls.items():
                py[name].append(timed(args.runs, call)[0])
    print(f"{args.size}, best of {args.rounds} x {args.runs} calls each, "
          f"nthreads {nt} ({os.cpu_count()} cores)")
    print("| stage | C++ ms | Python ms | Python / C++ |")
    print("| --- | --- | --- | --- |")
    for name in calls:
        cb, pb = min(cpp[name]), min(py[name])
        print(f"| {name} | {cb:.1f} | {pb:.1f} | {100.0 * (pb / cb - 1.0):+.1f} % |")


if __name__ == "__main__":
    main()
