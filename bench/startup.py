#!/usr/bin/env python3
"""Each dhdr tool's start-up: what it pays before main() and before it reads its input.

For every tool of --bin (and oiiotool, for comparison) the script prints one row:
  version s   median wall time of `TOOL --version` (start-up, then nothing)
  loader ms   the dynamic loader's own time for it (LD_DEBUG=statistics, its cycles over the
              TSC's rate from /proc/cpuinfo), and its relocations
  first read  seconds from execve to the openat of the input, on a tiny input (strace -f -ttt;
              strace slows every system call, so this is an upper bound), where one is made
  peak MiB    maximum resident set of `--version` (GNU /usr/bin/time -v)
  libraries   shared objects loaded (ldd | wc -l)

    python3 bench/startup.py --bin build/apps [--runs 5]
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
TESTDATA = os.path.join(HERE, "..", "testdata")
TOOLS = ["gbuffer", "light", "aa", "bloom", "motionblur", "tonemap", "ibl", "probes"]


def wall(cmd, runs):
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        subprocess.run(cmd, capture_output=True, check=False)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def tsc_hz():
    with open("/proc/cpuinfo") as f:
        m = re.search(r"cpu MHz\s*:\s*([\d.]+)", f.read())
    return float(m.group(1)) * 1e6 if m else float("nan")


def loader(cmd):
    env = dict(os.environ, LD_DEBUG="statistics")
    err = subprocess.run(cmd, capture_output=True, text=True, env=env).stderr
    cycles = re.search(r"total startup time in dynamic loader:\s*(\d+)", err)
    relocs = re.search(r"number of relocations:\s*(\d+)", err)
    return (int(cycles.group(1)) if cycles else 0), (int(relocs.group(1)) if relocs else 0)


def peak_mib(cmd):
    err = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True).stderr
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", err)
    return int(m.group(1)) / 1024 if m else float("nan")


def libraries(path):
    out = subprocess.run(["ldd", path], capture_output=True, text=True).stdout
    return len(out.strip().splitlines())


def first_read(cmd, input_path):
    """Seconds from execve to the openat of input_path, by strace's clock."""
    if not shutil.which("strace"):
        return float("nan")
    with tempfile.NamedTemporaryFile("r", suffix=".strace") as log:
        subprocess.run(["strace", "-f", "-ttt", "-e", "trace=execve,openat", "-o", log.name]
                       + cmd, capture_output=True)
        start = None
        for line in open(log.name):
            stamp = re.match(r"(?:\d+\s+)?([\d.]+) (\w+)\(", line)
            if not stamp:
                continue
            if stamp.group(2) == "execve" and start is None:
                start = float(stamp.group(1))
            if stamp.group(2) == "openat" and os.path.basename(input_path) in line:
                return float(stamp.group(1)) - start
    return float("nan")


def tiny_inputs(binary, tmp):
    """A tiny scene's G-buffer, lit frame and environment for each tool to read."""
    scene = os.path.join(TESTDATA, "cornell_box.gltf")
    gbuf, lit, env = (os.path.join(tmp, n) for n in ("g.exr", "l.exr", "env.exr"))
    subprocess.run([os.path.join(binary, "dhdr-gbuffer"), scene, "--size", "16x12", "-o", gbuf,
                    "-q"], check=True)
    lights = os.path.join(TESTDATA, "cornell_box.lights.json")
    subprocess.run([os.path.join(binary, "dhdr-light"), gbuf, "--lights", lights, "-o", lit, "-q"],
                   check=True)
    subprocess.run(["oiiotool", "--pattern", "constant:color=0.5,0.6,0.7", "32x16", "3", "-d",
                    "half", "-o", env], check=True)
    out = os.path.join(tmp, "out")
    return {
        "gbuffer": ([scene, "--size", "16x12", "-o", out + ".exr"], scene),
        "light": ([gbuf, "--lights", lights, "-o", out + ".exr"], gbuf),
        "aa": ([lit, "--gbuffer", gbuf, "-o", out + ".exr"], lit),
        "bloom": ([lit, "-o", out + ".exr"], lit),
        "motionblur": ([lit, "--gbuffer", gbuf, "-o", out + ".exr"], lit),
        "tonemap": ([lit, "-o", out + ".png"], lit),
        "ibl": ([env, "-o", out + ".exr"], env),
        "probes": ([scene, "--lights", lights, "-o", out + ".exr"], scene),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", required=True)
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    hz = tsc_hz()
    print("| program | version s | loader ms | relocations | first read s | peak MiB | "
          "libraries |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as tmp:
        inputs = tiny_inputs(args.bin, tmp)
        programs = [("dhdr-" + t, os.path.join(args.bin, "dhdr-" + t)) for t in TOOLS]
        programs.append(("oiiotool", shutil.which("oiiotool")))
        for name, path in programs:
            version = [path, "--version"] if name != "oiiotool" else [path, "--help"]
            cycles, relocs = loader(version)
            tool = name.replace("dhdr-", "")
            first = (first_read([path] + inputs[tool][0], inputs[tool][1])
                     if tool in inputs else float("nan"))
            print(f"| {name} | {wall(version, args.runs):.3f} | {cycles / hz * 1e3:.0f} "
                  f"| {relocs} | {first:.3f} | {peak_mib(version):.0f} "
                  f"| {libraries(path)} |", flush=True)


if __name__ == "__main__":
    main()
