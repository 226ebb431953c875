#!/usr/bin/env bash
# The reference path tracer beside the fast paths (docs/gi.md): the Cornell box lit by its own
# lights, direct light only | with probes | path traced (--gi path), at one exposure.
# Writes OUT/gi_path.png. About a minute on two cores (256 paths a pixel).
# Usage: scripts/path_demo.sh TOOLS_DIR OUT_DIR [SPP]
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
spp=${3:-256}
here=$(cd "$(dirname "$0")/.." && pwd)
scene="$here/testdata/cornell_box.gltf"
mkdir -p "$out"
"$tools/dhdr-probes" "$scene" --spacing 0.1 -o "$out/path.probes.exr" -q
"$tools/dhdr-gbuffer" "$scene" --size 320x320 -o "$out/path.gbuf.exr" -q
"$tools/dhdr-light" "$out/path.gbuf.exr" --scene "$scene" -o "$out/path_direct.hdr.exr" -q
"$tools/dhdr-light" "$out/path.gbuf.exr" --scene "$scene" --probes "$out/path.probes.exr" \
  -o "$out/path_probes.hdr.exr" -q
"$tools/dhdr-light" "$out/path.gbuf.exr" --scene "$scene" --gi path --spp "$spp" \
  -o "$out/path_traced.hdr.exr" -v
for name in direct probes traced; do
  "$tools/dhdr-tonemap" "$out/path_$name.hdr.exr" --op exposure --exposure -0.5 \
    -o "$out/path_$name.png" -q
done
oiiotool "$out/path_direct.png" "$out/path_probes.png" "$out/path_traced.png" --mosaic 3x1 \
  -o "$out/gi_path.png"
echo "$out/gi_path.png"
