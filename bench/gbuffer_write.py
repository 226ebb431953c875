#!/usr/bin/env python3
"""dhdr-gbuffer's trace and write times per compression (issue 47).

Runs `dhdr-gbuffer -v` on testdata scenes at the sizes given, once per compression, `--runs`
times each (alternating builds when --baseline is given), and prints the medians of what the
tool reports (trace, write = the rest of the frame after tracing), the process's CPU time
(user + sys) and wall time from GNU time, and the file's size. The deep row is the Cornell box
with its glass pane (a deep file: one total time).

    python3 bench/gbuffer_write.py --bin build/apps [--baseline /work/main/build/apps]
        [--sizes 1920x1080,3840x2160] [--runs 3]
"""
import argparse
import os
import re
import statistics
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
TESTDATA = os.path.join(HERE, "..", "testdata")


def run(binary, scene, size, compression, out):
    cmd = ["/usr/bin/time", "-f", "TIME %U %S %e %M", os.path.join(binary, "dhdr-gbuffer"),
           os.path.join(TESTDATA, scene), "--size", size, "-o", out, "-v"]
    if compression:
        cmd += ["--compression", compression]
    p = subprocess.run(cmd, capture_output=True, text=True, check=True)
    m = re.search(r"trace (\d+) ms, write (\d+) ms", p.stderr)
    d = re.search(r"deep: .*; (\d+) ms", p.stderr)
    t = re.search(r"TIME ([\d.]+) ([\d.]+) ([\d.]+) (\d+)", p.stderr)
    return {
        "trace": int(m.group(1)) / 1000 if m else float("nan"),
        "write": int(m.group(2)) / 1000 if m else float("nan"),
        "deep": int(d.group(1)) / 1000 if d else float("nan"),
        "cpu": float(t.group(1)) + float(t.group(2)),
        "wall": float(t.group(3)),
        "mib": int(t.group(4)) / 1024,
        "bytes": os.path.getsize(out),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", required=True)
    ap.add_argument("--baseline", help="another build's apps folder, run alternately")
    ap.add_argument("--sizes", default="1920x1080,3840x2160")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--scenes", default="shot.gltf,cornell_box.gltf")
    ap.add_argument("--compressions", default=",zip,rle,none")
    args = ap.parse_args()
    builds = [("this", args.bin)] + ([("baseline", args.baseline)] if args.baseline else [])
    cases = [(s, c) for s in args.scenes.split(",") for c in args.compressions.split(",")]
    cases.append(("cornell_glass.gltf", ""))
    print("| build | scene | size | compression | trace s | write s | deep s | CPU s | wall s "
          "| peak MiB | MB |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as tmp:
        for size in args.sizes.split(","):
            for scene, compression in cases:
                results = {name: [] for name, _ in builds}
                for _ in range(args.runs):
                    for name, binary in builds:
                        out = os.path.join(tmp, name + ".exr")
                        results[name].append(run(binary, scene, size, compression, out))
                for name, _ in builds:
                    r = results[name]
                    med = {k: statistics.median(x[k] for x in r) for k in r[0]}
                    print(f"| {name} | {scene} | {size} | {compression or 'default'} "
                          f"| {med['trace']:.2f} | {med['write']:.2f} | {med['deep']:.2f} "
                          f"| {med['cpu']:.2f} | {med['wall']:.2f} | {med['mib']:.0f} "
                          f"| {med['bytes'] / 1e6:.1f} |", flush=True)


if __name__ == "__main__":
    main()
