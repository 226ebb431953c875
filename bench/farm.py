#!/usr/bin/env python3
"""dhdr-farm's cost over running the tools directly: the farm tests' pipeline (G-buffer,
light, bloom, tone mapping with adaptation) over --frames at --size, run as one process per
stage, through `dhdr-farm --engine local` (-j 1 and -j 2), and on a single-node Slurm cluster
started for the purpose (tests/farm/slurm_cluster.py; needs root). Wall seconds each.

    python3 bench/farm.py --bin build/apps [--frames 24] [--size 320x240] [--chunk 4]
"""
import argparse
import os
import shutil
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "farm"))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--chunk", type=int, default=4)
    args = ap.parse_args()
    os.environ["DHDR_BIN"] = os.path.abspath(args.bin)
    import farm_fixture as fx
    from slurm_cluster import SlurmCluster
    fx.SIZE = args.size
    fx.FRAMES = range(1, args.frames + 1)
    work = tempfile.mkdtemp(prefix="dhdr_bench_farm_")
    os.chmod(work, 0o755)
    frames = "1-%d" % args.frames
    rows = []
    try:
        fx.write_lights(work)
        t = time.perf_counter()
        fx.reference(work)
        rows.append(("tools directly, one process per stage", time.perf_counter() - t))
        for jobs in (1, 2):
            name = "local%d" % jobs
            pipeline = fx.write_pipeline(work, name)
            t = time.perf_counter()
            r = fx.farm("submit", pipeline, "--frames", frames, "--chunk", str(args.chunk),
                        "--engine", "local", "-j", str(jobs), "-q", cwd=work)
            if r.returncode != 0:
                sys.exit("bench: dhdr-farm failed:\n" + r.stderr)
            rows.append(("dhdr-farm --engine local -j %d" % jobs, time.perf_counter() - t))
        if os.geteuid() == 0:
            with SlurmCluster() as cluster:
                pipeline = fx.write_pipeline(work, "slurm")
                t = time.perf_counter()
                r = fx.farm("submit", pipeline, "--frames", frames, "--chunk", str(args.chunk),
                            "--wait", "-q", cwd=work, env=cluster.env)
                if r.returncode != 0:
                    sys.exit("bench: dhdr-farm on Slurm failed:\n" + r.stdout + r.stderr)
                rows.append(("dhdr-farm on Slurm (1 node, %d CPUs, 1 per task)" % cluster.cpus,
                             time.perf_counter() - t))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("%d frames of %s in chunks of %d, %d cores" % (args.frames, args.size, args.chunk,
                                                        os.cpu_count()))
    for name, wall in rows:
        print("%-50s %8.2f s" % (name, wall))


if __name__ == "__main__":
    main()
