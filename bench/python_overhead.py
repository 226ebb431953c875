#!/usr/bin/env python3
"""The Python module's calls against the same library calls in C++ on a 1920x1080 frame
(issue 25: at most 5 % more). Renders the Cornell box's G-buffer with dhdr-gbuffer, then for
light, tone_map, bloom and edge_aa alternates, call by call, the library call timed in C++
inside this process on the same memory (dhdr._dhdr._library_call_ms) and the Python call
(dhdr.tone_map(hdr) ...), each making a new result; the shared machine's load then falls on
both alike, and the best of --runs of each is compared. dhdr-bench-stages (bench/stages.cpp),
the same calls in a C++ program of their own, is run --rounds times for reference.

    python3 bench/python_overhead.py --build build [--size 1920x1080] [--runs 15]
                                     [--rounds 2] [--threads N]
"""
import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=str(ROOT / "build"))
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--runs", type=int, default=15)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--threads", type=int, default=0)
    args = ap.parse_args()
    build = pathlib.Path(args.build)
    sys.path.insert(0, str(build / "python"))
    import numpy as np
    import dhdr

    lights = str(ROOT / "testdata" / "cornell_box.lights.json")
    nt = args.threads
    with tempfile.TemporaryDirectory() as tmp:
        g_path = pathlib.Path(tmp) / "g.exr"
        subprocess.run([build / "apps" / "dhdr-gbuffer", ROOT / "testdata" / "cornell_box.gltf",
                        "--size", args.size, "-q", "-o", g_path], check=True)
        process = {}
        for _ in range(args.rounds):
            out = subprocess.run([build / "dhdr-bench-stages", g_path, lights, "5", str(nt)],
                                 check=True, capture_output=True, text=True).stdout
            for line in out.splitlines():
                name, best, _median = line.split()
                process[name] = min(process.get(name, float("inf")), float(best))
        g = dhdr.read_gbuffer(str(g_path))
    hdr = dhdr.light(g, lights)
    n = g.channels.index("N.X")
    normal = np.ascontiguousarray(g.pixels[..., n:n + 3])
    depth = np.ascontiguousarray(g["Z"])
    stages = {
        "light": (lambda: dhdr.light(g, lights, nthreads=nt), dict(src=g, lights=lights)),
        "tone_map": (lambda: dhdr.tone_map(hdr, nthreads=nt), dict(src=hdr)),
        "bloom": (lambda: dhdr.bloom(hdr, nthreads=nt), dict(src=hdr)),
        "edge_aa": (lambda: dhdr.edge_aa(hdr, normal=normal, depth=depth, nthreads=nt),
                    dict(src=hdr, normal=normal, depth=depth)),
    }
    print(f"{args.size}, nthreads {nt} ({os.cpu_count()} cores), best of {args.runs} "
          f"alternating calls; a C++ program: best of {args.rounds} x 5")
    print("| stage | C++ program ms | C++ in-process ms | Python ms | Python / C++ in-process |")
    print("| --- | --- | --- | --- | --- |")
    for name, (call, library) in stages.items():
        lib, py = [], []
        for _ in range(args.runs):
            lib.append(dhdr._dhdr._library_call_ms(name, nthreads=nt, **library))
            t = time.perf_counter()
            call()
            py.append((time.perf_counter() - t) * 1000.0)
        print(f"| {name} | {process[name]:.1f} | {min(lib):.1f} | {min(py):.1f} | "
              f"{100.0 * (min(py) / min(lib) - 1.0):+.1f} % |")
    # What a call costs beyond the library's work, measured where that work is nothing: a 2x2
    # image, best of 2000 (microseconds; the conversions, the wrapping, the result's capsule).
    tiny = np.ones((2, 2, 4), np.float32)
    print("\nfixed cost per call (2x2 image, best of 2000, microseconds):")
    for name, call, library in [
            ("tone_map", lambda: dhdr.tone_map(tiny), dict(src=tiny)),
            ("bloom", lambda: dhdr.bloom(tiny), dict(src=tiny))]:
        lib, py = [], []
        for _ in range(2000):
            lib.append(dhdr._dhdr._library_call_ms(name, **library) * 1000.0)
            t = time.perf_counter()
            call()
            py.append((time.perf_counter() - t) * 1e6)
        print(f"  {name}: library {min(lib):.1f}, Python call {min(py):.1f}, "
              f"difference {min(py) - min(lib):.1f}")


if __name__ == "__main__":
    main()
