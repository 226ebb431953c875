#!/usr/bin/env bash
# The light objects bounce onto a shadow catcher (docs/ibl.md, "The ground plane"): the bundled
# spheres on the ground plane under Poly Haven's "sunrise" (Debian's blender-data, CC0), its
# sun split off, composited over the sky, without (--catcher-bounce 0) and with the bounce (the
# default). Writes OUT/catcher_bounce.png: top the composites, bottom the catcher's alpha.
# Usage: scripts/catcher_demo.sh TOOLS_DIR OUT_DIR [HDRI]
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
hdri=${3:-/usr/share/blender/datafiles/studiolights/world/sunrise.exr}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
if [ ! -f "$hdri" ]; then
  echo "catcher_demo: $hdri not found (apt-get install blender-data)" >&2
  exit 1
fi
cp "$hdri" "$out/catcher_sky.exr"
"$tools/dhdr-gbuffer" "$here/testdata/spheres.gltf" --size 480x270 --ground-plane \
  --lookat 0.6,0.9,3.6,0.3,0.35,0 -o "$out/catcher.gbuf.exr" -q
printf '{"lights": [{"type": "environment", "name": "sky", "image": "catcher_sky.exr", "rotation": 200}]}\n' \
  >"$out/catcher.lights.json"
for n in 0 16; do
  "$tools/dhdr-light" "$out/catcher.gbuf.exr" --scene "$here/testdata/spheres.gltf" \
    --lights "$out/catcher.lights.json" --catcher-bounce $n -o "$out/catcher_$n.exr" -q
  "$tools/dhdr-light" "$out/catcher.gbuf.exr" --scene "$here/testdata/spheres.gltf" \
    --lights "$out/catcher.lights.json" --catcher-bounce $n --plate env \
    -o "$out/catcher_$n.comp.exr" -q
  "$tools/dhdr-tonemap" "$out/catcher_$n.comp.exr" -o "$out/catcher_$n.png" -q
  oiiotool "$out/catcher_$n.exr" --ch R=A,G=A,B=A -d uint8 -o "$out/catcher_${n}_alpha.png"
done
oiiotool "$out/catcher_0.png" "$out/catcher_16.png" "$out/catcher_0_alpha.png" \
  "$out/catcher_16_alpha.png" --mosaic 2x2 -o "$out/catcher_bounce.png"
echo "$out/catcher_bounce.png"
