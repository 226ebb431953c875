#!/usr/bin/env bash
# The motion layer (docs/animation.md): frame 24 of testdata/cornell_animated.gltf, lit and
# tone-mapped, with the forward motion of a grid of pixels drawn over it as arrows (yellow,
# towards the next frame's position, scaled ×12 to be seen; red dots: the grid). Writes
# docs/images/motion_vectors.png.
# Usage: scripts/motion_demo.sh TOOLS_DIR OUT_DIR   (e.g. build/apps out/demo)
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
here=$(cd "$(dirname "$0")/.." && pwd)
scene="$here/testdata/cornell_animated.gltf"
mkdir -p "$out"

step() { echo "== $*"; "$@"; }
step "$tools/dhdr-gbuffer" "$scene" --size 512x512 --frame 24 -o "$out/motion.gbuf.exr"
step "$tools/dhdr-light" "$out/motion.gbuf.exr" --lights "$here/testdata/cornell_box.lights.json" \
  -o "$out/motion.hdr.exr"
step "$tools/dhdr-tonemap" "$out/motion.hdr.exr" -o "$out/motion_base.png"
oiiotool "$out/motion.gbuf.exr" --ch motion.X,motion.Y,motion.Z,motion.W -o "$out/motion.exr"
oiiotool --dumpdata "$out/motion.exr" >"$out/motion.txt"

# Forward motion is −(Z, W) in pixels with y up; in the picture (y down) that is (−Z, +W).
python3 - "$out/motion.txt" "$out/motion_base.png" "$here/docs/images/motion_vectors.png" <<'PY'
import math
import re
import subprocess
import sys

dump, base, target = sys.argv[1:4]
step, scale = 32, 12.0
args = ["oiiotool", base]
for line in open(dump):
    m = re.match(r"\s*Pixel \((\d+), (\d+)\):\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)", line)
    if not m:
        continue
    x, y = int(m.group(1)), int(m.group(2))
    if x % step != step // 2 or y % step != step // 2:
        continue
    z, w = float(m.group(5)), float(m.group(6))
    dx, dy = -z * scale, w * scale
    ex, ey = x + dx, y + dy
    args += ["--point:color=1,0.2,0.2", "%d,%d" % (x, y)]
    if abs(dx) + abs(dy) < 0.5:
        continue
    args += ["--line:color=1,0.9,0.1", "%d,%d,%d,%d" % (x, y, round(ex), round(ey))]
    # An arrow head: two short strokes back from the tip, ±25 degrees off the shaft.
    length = math.hypot(dx, dy)
    ux, uy = dx / length, dy / length
    for s in (1, -1):
        c, sn = math.cos(math.radians(25)), s * math.sin(math.radians(25))
        hx, hy = -(ux * c - uy * sn) * 5, -(ux * sn + uy * c) * 5
        args += ["--line:color=1,0.9,0.1", "%d,%d,%d,%d" % (round(ex), round(ey),
                                                            round(ex + hx), round(ey + hy))]
args += ["-o", target]
subprocess.run(args, check=True)
print("wrote", target)
PY
