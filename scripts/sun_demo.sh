#!/usr/bin/env bash
# The sun of a real HDRI split off as a light (docs/ibl.md, "The sun"): the bundled spheres on
# a shadow-catching ground plane under Poly Haven's "sunrise" (Debian's blender-data, CC0),
# with the sun kept in the sky ("sun": "off") and split off (the default), at the defaults of
# scripts/ibl_demo.sh. Writes OUT/sun_off.png, OUT/sun_split.png and OUT/sun_compare.png.
# Usage: scripts/sun_demo.sh TOOLS_DIR OUT_DIR [HDRI]
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
hdri=${3:-/usr/share/blender/datafiles/studiolights/world/sunrise.exr}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
if [ ! -f "$hdri" ]; then
  echo "sun_demo: $hdri not found (apt-get install blender-data)" >&2
  exit 1
fi
cp "$hdri" "$out/sun_sky.exr"
"$tools/dhdr-gbuffer" "$here/testdata/spheres.gltf" --size 960x540 --ground-plane \
  --lookat 0.6,0.9,3.6,0.3,0.35,0 -o "$out/sun_spheres.gbuf.exr" -q
for mode in off split; do
  sun=$([ "$mode" = off ] && echo ', "sun": "off"' || true)
  printf '{"lights": [{"type": "environment", "name": "sky", "image": "sun_sky.exr", "rotation": 200%s}]}\n' \
    "$sun" >"$out/sun_$mode.lights.json"
  "$tools/dhdr-light" "$out/sun_spheres.gbuf.exr" --scene "$here/testdata/spheres.gltf" \
    --lights "$out/sun_$mode.lights.json" --env-samples 16 --ao rt --ao-distance 0.5 \
    --plate env -o "$out/sun_$mode.hdr.exr" -q
  "$tools/dhdr-tonemap" "$out/sun_$mode.hdr.exr" -o "$out/sun_$mode.png" -q
done
oiiotool "$out/sun_off.png" "$out/sun_split.png" --mosaic 2x1 -o "$out/sun_compare.png"
echo "$out/sun_compare.png"
