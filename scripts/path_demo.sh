#!/usr/bin/env bash
# The reference path tracer beside the fast paths (docs/gi.md): the Cornell box with a gold
# tall block (testdata/cornell_gold.gltf) lit by its own lights, direct light only | with
# probes | probes and the specular indirect light (dhdr-light's default with --scene and
# --probes) | path traced (--gi path), at one exposure. Writes OUT/gi_path.png. About a minute
# on two cores (256 paths a pixel).
# Usage: scripts/path_demo.sh TOOLS_DIR OUT_DIR [SPP]
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
spp=${3:-256}
here=$(cd "$(dirname "$0")/.." && pwd)
scene="$here/testdata/cornell_gold.gltf"
mkdir -p "$out"
"$tools/dhdr-probes" "$scene" -o "$out/path.probes.exr" -q
"$tools/dhdr-gbuffer" "$scene" --size 320x320 -o "$out/path.gbuf.exr" -q
light=("$tools/dhdr-light" "$out/path.gbuf.exr" --scene "$scene")
"${light[@]}" --gi direct --specular-samples 0 -o "$out/path_direct.hdr.exr" -q
"${light[@]}" --specular-samples 0 --probes "$out/path.probes.exr" -o "$out/path_probes.hdr.exr" -q
"${light[@]}" --probes "$out/path.probes.exr" -o "$out/path_specular.hdr.exr" -q
"${light[@]}" --gi path --spp "$spp" -o "$out/path_traced.hdr.exr" -v
for name in direct probes specular traced; do
  "$tools/dhdr-tonemap" "$out/path_$name.hdr.exr" --op exposure --exposure -0.5 \
    -o "$out/path_$name.png" -q
done
oiiotool "$out/path_direct.png" "$out/path_probes.png" "$out/path_specular.png" \
  "$out/path_traced.png" --mosaic 4x1 -o "$out/gi_path.png"
echo "$out/gi_path.png"
