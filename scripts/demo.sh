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
# The README's "pipeline, by hand" block, as written: the Cornell box with its own lights,
# soft shadows from the glowing ceiling panel and indirect light from the probes dhdr-light bakes.
step bash "$here/scripts/readme_chain.sh" "$tools" "$out"
echo "== first picture: $out/cornell.png"

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
for f in cornell.gbuf.exr cornell.hdr.exr cornell.aa.exr cornell.bloom.exr cornell.png \
  sky.exr sky.ibl.exr spheres.gbuf.exr spheres.hdr.exr spheres.png \
  glass.gbuf.exr glass.hdr.exr glass.deep.exr glass.png cornell.probes.exr gi.png \
  shot_sheet.png shot_blur.png; do
  echo "  $out/$f"
done
echo "  out/shot/shot.0001.png ... shot.0024.png (and each stage's EXRs beside them)"
