#!/usr/bin/env bash
# Image-based lighting and AR compositing on the bundled spheres (docs/ibl.md): a sky with a
# sun made with oiiotool, baked by dhdr-ibl; the spheres on a shadow-catching ground plane lit
# by it, with environment shadows and AO, composited over the environment as the plate.
# Usage: scripts/ibl_demo.sh TOOLS_DIR OUT_DIR   (make demo passes build/apps out/demo)
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"

step() { echo "== $*"; "$@"; }
# The sky: a vertical gradient, a darker ground half, and a sun (radiance 30,000) up and to
# the right of the camera's view.
step oiiotool --pattern fill:top=0.35,0.55,1.0:bottom=0.9,0.9,0.95 2048x512 3 \
  --pattern fill:top=0.25,0.22,0.2:bottom=0.12,0.1,0.09 2048x512 3 --mosaic 1x2 \
  --box:color=30000,28000,24000:fill=1 1530,230,1542,242 -d float -o "$out/sky.exr"
step "$tools/dhdr-ibl" "$out/sky.exr" -o "$out/sky.ibl.exr" -v
printf '{"lights": [{"type": "environment", "name": "sky", "image": "sky.ibl.exr"}]}\n' \
  >"$out/sky.lights.json"
step "$tools/dhdr-gbuffer" "$here/testdata/spheres.gltf" --size 960x540 --ground-plane \
  -o "$out/spheres.gbuf.exr" -v
step "$tools/dhdr-light" "$out/spheres.gbuf.exr" --scene "$here/testdata/spheres.gltf" \
  --lights "$out/sky.lights.json" --env-samples 16 --ao rt --ao-distance 0.5 --plate env \
  -o "$out/spheres.hdr.exr" -v
step "$tools/dhdr-tonemap" "$out/spheres.hdr.exr" -o "$out/spheres.png" -v
