#!/usr/bin/env bash
# Transparent surfaces (docs/gbuffer.md, docs/lighting.md): the Cornell box with a glass pane
# (alpha 0.4) and a card with holes behind it. dhdr-gbuffer writes a deep G-buffer (glass, card
# and wall in one pixel); dhdr-light lights every sample, shadows through the glass and the
# holes, composites them, and writes the lit samples as a deep EXR too.
# Usage: scripts/glass_demo.sh TOOLS_DIR OUT_DIR   (make demo passes build/apps out/demo)
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
here=$(cd "$(dirname "$0")/.." && pwd)
scene="$here/testdata/cornell_glass.gltf"
mkdir -p "$out"

step() { echo "== $*"; "$@"; }
step "$tools/dhdr-gbuffer" "$scene" --size 1024x1024 -o "$out/glass.gbuf.exr" -v
step "$tools/dhdr-light" "$out/glass.gbuf.exr" --scene "$scene" \
  --lights "$here/testdata/cornell_box.lights.json" --ao rt --ao-distance 0.1 \
  --deep-out "$out/glass.deep.exr" -o "$out/glass.hdr.exr" -v
step "$tools/dhdr-aa" "$out/glass.hdr.exr" --gbuffer "$out/glass.gbuf.exr" -o "$out/glass.aa.exr" -v
step "$tools/dhdr-tonemap" "$out/glass.aa.exr" -o "$out/glass.png" -v
