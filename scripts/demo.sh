#!/usr/bin/env bash
# Runs the whole pipeline on the bundled Cornell box and prints where each stage's output is.
# Usage: scripts/demo.sh TOOLS_DIR OUT_DIR   (make demo passes build/apps out/demo)
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
here=$(cd "$(dirname "$0")/.." && pwd)
scene="$here/testdata/cornell_box.gltf"
lights="$here/testdata/cornell_box.lights.json"
mkdir -p "$out"

step() { echo "== $*"; "$@"; }
step "$tools/dhdr-gbuffer" "$scene" --size 1024x1024 -o "$out/cornell.gbuf.exr" -v
step "$tools/dhdr-light" "$out/cornell.gbuf.exr" --lights "$lights" \
  -o "$out/cornell.hdr.exr" -v
step "$tools/dhdr-aa" "$out/cornell.hdr.exr" --gbuffer "$out/cornell.gbuf.exr" \
  -o "$out/cornell.aa.exr" -v
step "$tools/dhdr-bloom" "$out/cornell.aa.exr" -o "$out/cornell.bloom.exr" -v
step "$tools/dhdr-tonemap" "$out/cornell.bloom.exr" -o "$out/cornell.png" -v

echo
echo "Outputs:"
for f in cornell.gbuf.exr cornell.hdr.exr cornell.aa.exr cornell.bloom.exr cornell.png; do
  echo "  $out/$f"
done
