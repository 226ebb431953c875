#!/usr/bin/env bash
# The room in the metal (docs/gi.md, "Specular indirect light"): the Cornell box with a gold
# tall block (testdata/cornell_gold.gltf), direct light only | with the specular indirect light
# (the default with --scene) | path traced, at one exposure. Writes OUT/gi_specular.png. About
# half a minute on two cores (the path tracer's 256 paths a pixel).
# Usage: scripts/specular_demo.sh TOOLS_DIR OUT_DIR [SPP]
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
spp=${3:-256}
here=$(cd "$(dirname "$0")/.." && pwd)
scene="$here/testdata/cornell_gold.gltf"
mkdir -p "$out"
"$tools/dhdr-gbuffer" "$scene" --size 320x320 -o "$out/gold.gbuf.exr" -q
"$tools/dhdr-light" "$out/gold.gbuf.exr" --scene "$scene" --gi direct --specular-samples 0 \
  -o "$out/gold_direct.hdr.exr" -q
"$tools/dhdr-light" "$out/gold.gbuf.exr" --scene "$scene" --gi direct \
  -o "$out/gold_specular.hdr.exr" -v
"$tools/dhdr-light" "$out/gold.gbuf.exr" --scene "$scene" --gi path --spp "$spp" \
  -o "$out/gold_path.hdr.exr" -q
for name in direct specular path; do
  "$tools/dhdr-tonemap" "$out/gold_$name.hdr.exr" --op exposure --exposure -0.5 \
    -o "$out/gold_$name.png" -q
done
oiiotool "$out/gold_direct.png" "$out/gold_specular.png" "$out/gold_path.png" --mosaic 3x1 \
  -o "$out/gi_specular.png"
echo "$out/gi_specular.png"
