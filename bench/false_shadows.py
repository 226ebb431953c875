#!/usr/bin/env python3
"""False shadows on real data, under each Embree kernel (issue 21).

Renders the Khronos glTF-Asset-Generator's Mesh_PrimitiveMode_04 (a lone quad, from Debian's
assimp-testmodels) from 1, 30, 300 and 3000 units away, the view filling the frame, lit by two
suns, with and without shadow rays: a quad cannot shadow itself, so every pixel that differs
is a false shadow. Prints the count per distance and kernel, with wall time.

  python3 bench/false_shadows.py --bin build/apps
"""
import argparse
import math
import os
import subprocess
import tempfile
import time

MODEL = ("/usr/share/assimp/models/glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/"
         "Mesh_PrimitiveMode_04.gltf")
LIGHTS = ('{"lights": [{"type": "directional", "direction": [-0.3, -0.8, -0.5], "intensity": 3},'
          ' {"type": "directional", "direction": [0.6, -0.5, -0.6], "intensity": 2}]}')


def kernels():
    flags = open("/proc/cpuinfo").read()
    out = ["sse4.2"]
    if " avx2 " in flags:
        out.append("avx2")
    if all(f" {f} " in flags for f in ("avx512f", "avx512bw", "avx512vl")):
        out.append("avx512")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", type=int, default=400)
    args = ap.parse_args()
    if not os.path.exists(MODEL):
        print("false_shadows: needs Debian's assimp-testmodels (apt-get install assimp-testmodels)")
        return 0
    tool = lambda name: os.path.join(args.bin, name)
    with tempfile.TemporaryDirectory() as d:
        lights = os.path.join(d, "suns.json")
        with open(lights, "w") as f:
            f.write(LIGHTS)
        print(f"{'distance':>8} {'kernel':>7} {'false':>6} {'pixels':>7} {'time':>7}")
        for distance in (1, 30, 300, 3000):
            fov = 2 * math.degrees(math.atan(0.6 / distance))
            for isa in kernels():
                env = dict(os.environ, DHDR_EMBREE_ISA=isa)
                t0 = time.time()
                g, s, n = (os.path.join(d, x) for x in ("g.exr", "s.exr", "n.exr"))
                subprocess.run([tool("dhdr-gbuffer"), MODEL, "--lookat",
                                f"0.2,0.3,{distance},0,0,0", "--fov", str(fov), "--size",
                                f"{args.size}x{args.size}", "-q", "-o", g], check=True, env=env)
                common = [tool("dhdr-light"), g, "--scene", MODEL, "--lights", lights, "--type",
                          "float", "-q"]
                subprocess.run(common + ["-o", s], check=True, env=env)
                subprocess.run(common + ["--no-shadows", "-o", n], check=True, env=env)
                wall = time.time() - t0
                diff = subprocess.run(["idiff", "-fail", "0", "-failpercent", "0", s, n],
                                      capture_output=True, text=True).stdout
                false = 0
                for line in diff.splitlines():
                    if "pixels" in line and "over" in line:
                        false = int(line.split()[0])
                        break
                print(f"{distance:>8} {isa:>7} {false:>6} {args.size * args.size:>7} "
                      f"{wall:>6.2f}s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
