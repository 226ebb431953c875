#!/usr/bin/env bash
# Global illumination from light probes (docs/gi.md): the Cornell box lit by its own lights
# without and with the probes dhdr-probes bakes, side by side.
# Usage: scripts/gi_demo.sh TOOLS_DIR OUT_DIR   (make demo passes build/apps out/demo)
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
here=$(cd "$(dirname "$0")/.." && pwd)
scene="$here/testdata/cornell_box.gltf"
mkdir -p "$out"

step() { echo "== $*"; "$@"; }
step "$tools/dhdr-probes" "$scene" -o "$out/cornell.probes.exr" -v
step "$tools/dhdr-gbuffer" "$scene" --size 640x640 -o "$out/gi.gbuf.exr" -v
for gi in off on; do
  probes=(--gi direct)
  [ "$gi" = on ] && probes=(--probes "$out/cornell.probes.exr")
  step "$tools/dhdr-light" "$out/gi.gbuf.exr" --scene "$scene" "${probes[@]}" \
    -o "$out/gi_$gi.hdr.exr" -v
  # One exposure for both, so that the indirect light shows as light added.
  step "$tools/dhdr-tonemap" "$out/gi_$gi.hdr.exr" --op exposure --exposure -0.5 \
    -o "$out/gi_$gi.png" -v
done
step oiiotool "$out/gi_off.png" "$out/gi_on.png" --mosaic 2x1 -o "$out/gi.png"
