#!/usr/bin/env bash
# Runs the whole pipeline on the bundled Cornell box and prints where each stage's output is.
# Usage: scripts/demo.sh TOOLS_DIR OUT_DIR   (make demo passes build/apps out/demo)
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
here=$(cd "$(dirname "$0")/.." && pwd)
scene="$here/testdata/cornell_box.gltf"
mkdir -p "$out"

step() { echo "== $*"; "$@"; }
# The scene's own lights (KHR_lights_punctual) travel to the lighting stage as a lights file;
# an ambient fill is added from a second one. --scene gives the lighting stage the scene's
# triangles: lights cast shadows, the ceiling's glowing panel lights the box (soft shadows),
# and --ao rt occludes the ambient fill within 10 cm.
step "$tools/dhdr-gbuffer" "$scene" --size 1024x1024 --lights-out "$out/cornell.lights.json" \
  -o "$out/cornell.gbuf.exr" -v
step "$tools/dhdr-light" "$out/cornell.gbuf.exr" --scene "$scene" \
  --lights "$out/cornell.lights.json" --lights "$here/testdata/cornell_box.fill.lights.json" \
  --ao rt --ao-distance 0.1 \
  -o "$out/cornell.hdr.exr" -v
step "$tools/dhdr-aa" "$out/cornell.hdr.exr" --gbuffer "$out/cornell.gbuf.exr" \
  -o "$out/cornell.aa.exr" -v
step "$tools/dhdr-bloom" "$out/cornell.aa.exr" -o "$out/cornell.bloom.exr" -v
step "$tools/dhdr-tonemap" "$out/cornell.bloom.exr" -o "$out/cornell.png" -v

# Image-based lighting and AR compositing: spheres on a shadow-catching ground plane under an
# HDR sky, composited over it (docs/ibl.md).
bash "$here/scripts/ibl_demo.sh" "$tools" "$out"

# Glass and cut-outs: a deep G-buffer lit sample by sample (docs/gbuffer.md).
bash "$here/scripts/glass_demo.sh" "$tools" "$out"

# Global illumination from light probes, without and with (docs/gi.md).
bash "$here/scripts/gi_demo.sh" "$tools" "$out"

# An animated shot (docs/animation.md): testdata/shot.gltf through the whole chain with motion
# blur and eye adaptation, run by dhdr-farm's local engine; a contact sheet and a frame
# without and with motion blur.
bash "$here/scripts/shot_demo.sh" "$tools" "$out"

echo
echo "Outputs:"
for f in cornell.gbuf.exr cornell.lights.json cornell.hdr.exr cornell.aa.exr cornell.bloom.exr cornell.png \
  sky.exr sky.ibl.exr spheres.gbuf.exr spheres.hdr.exr spheres.png \
  glass.gbuf.exr glass.hdr.exr glass.deep.exr glass.png cornell.probes.exr gi.png \
  shot_sheet.png shot_blur.png; do
  echo "  $out/$f"
done
echo "  out/shot/shot.0001.png ... shot.0024.png (and each stage's EXRs beside them)"
