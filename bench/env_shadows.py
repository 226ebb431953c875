#!/usr/bin/env python3
"""Environment shadows on real skies: black pixels and noise against a converged render (issue 22).

For each Poly Haven HDRI that Debian's blender-data ships (studiolights/world, CC0) and the
generated sky of scripts/ibl_demo.sh (a 0.4° sun of radiance 30,000): the bundled spheres on
a shadow-catching ground plane (dhdr-gbuffer --ground-plane), lit with --scene at
--env-samples 16, 64 and 256 (--samples). Prints, per sample count, the covered pixels that are exactly
black although the unshadowed render lights them, the RMS error against a 1024-sample render
without denoising (idiff), and wall time; --denoise off measures the per-pixel estimates.

  python3 bench/env_shadows.py --bin build/apps
"""
import argparse
import glob
import os
import subprocess
import tempfile
import time

WORLD = "/usr/share/blender/datafiles/studiolights/world"
HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(HERE, "testdata", "spheres.gltf")


def pixels(path):
    """(R+G+B, A) of every pixel, from oiiotool --dumpdata."""
    out = subprocess.run(["oiiotool", "--dumpdata", path],
                         capture_output=True, text=True, check=True).stdout
    values = []
    for line in out.splitlines():
        if ":" not in line or not line.lstrip().startswith("Pixel"):
            continue
        v = [float(x) for x in line.split(":", 1)[1].split()]
        values.append((v[0] + v[1] + v[2], v[3]))
    return values


def rms(a, b):
    out = subprocess.run(["idiff", "-v", "-fail", "1e9", a, b], capture_output=True, text=True).stdout
    for line in out.splitlines():
        if "RMS error" in line:
            return float(line.split()[-1])
    return float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", default="320x180")
    ap.add_argument("--denoise", default="on", choices=["on", "off"])
    ap.add_argument("--samples", default="16,64,256", help="--env-samples values, comma-separated")
    args = ap.parse_args()
    tool = lambda name: os.path.join(args.bin, name)
    with tempfile.TemporaryDirectory() as d:
        skies = sorted(glob.glob(os.path.join(WORLD, "*.exr")))
        sky = os.path.join(d, "generated.exr")
        subprocess.run(["oiiotool", "--pattern", "fill:top=0.35,0.55,1.0:bottom=0.9,0.9,0.95",
                        "2048x512", "3", "--pattern", "fill:top=0.25,0.22,0.2:bottom=0.12,0.1,0.09",
                        "2048x512", "3", "--mosaic", "1x2", "--box:color=30000,28000,24000:fill=1",
                        "1530,230,1542,242", "-d", "float", "-o", sky], check=True)
        skies.append(sky)
        if len(skies) == 1:
            print("env_shadows: blender-data is not installed; only the generated sky")
        g = os.path.join(d, "g.exr")
        subprocess.run([tool("dhdr-gbuffer"), SCENE, "--size", args.size, "--ground-plane", "-q",
                        "-o", g], check=True)
        print(f"{'sky':>10} {'samples':>7} {'black':>6} {'covered':>7} {'RMS':>8} {'time':>7}")
        for path in skies:
            name = os.path.splitext(os.path.basename(path))[0]
            ibl = os.path.join(d, name + ".ibl.exr")
            subprocess.run([tool("dhdr-ibl"), path, "-o", ibl, "-q"], check=True)
            lights = os.path.join(d, name + ".json")
            with open(lights, "w") as f:
                f.write('{"lights": [{"type": "environment", "image": "%s"}]}' % ibl)

            def light(samples, out):
                t0 = time.time()
                subprocess.run([tool("dhdr-light"), g, "--scene", SCENE, "--lights", lights,
                                "--type", "float", "-q", "--env-samples", str(samples),
                                "--denoise", args.denoise if samples < 1024 else "off", "-o",
                                out], check=True)
                return time.time() - t0

            open_ = os.path.join(d, "open.exr")
            subprocess.run([tool("dhdr-light"), g, "--lights", lights, "--type", "float", "-q",
                            "-o", open_], check=True)
            reference = os.path.join(d, "ref.exr")
            light(1024, reference)
            unshadowed = pixels(open_)
            for samples in [int(v) for v in args.samples.split(",")]:
                out = os.path.join(d, f"lit{samples}.exr")
                wall = light(samples, out)
                lit = pixels(out)
                covered = sum(1 for s, a in unshadowed if a > 0)
                black = sum(1 for (s, a), (l, _) in zip(unshadowed, lit) if a > 0 and s > 0 and l == 0)
                print(f"{name:>10} {samples:>7} {black:>6} {covered:>7} {rms(out, reference):>8.5f} "
                      f"{wall:>6.2f}s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
