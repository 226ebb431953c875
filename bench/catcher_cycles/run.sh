#!/usr/bin/env bash
# dhdr's shadow catcher against Blender Cycles' (bench/README.md, session 10): the bundled
# spheres on the ground plane under Poly Haven's "sunrise" (blender-data), 480x270; dhdr with
# --catcher-bounce 0, 16 (default) and 256 undenoised; Cycles at 1024 samples (and 64, for its
# own noise), no denoiser, the catcher white 0.8 diffuse. Prints alpha errors and IoUs on the
# ground pixels. Needs apt packages blender and python3-openimageio.
# Usage: bench/catcher_cycles/run.sh TOOLS_DIR WORK_DIR [HDRI]
set -euo pipefail
tools=${1:-build/apps}
work=${2:-/tmp/catcher_cycles}
hdri=${3:-/usr/share/blender/datafiles/studiolights/world/sunrise.exr}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
mkdir -p "$work"
cp "$hdri" "$work/sunrise.exr"
export DHDR_SCENE="$root/testdata/spheres.gltf" DHDR_HDRI="$work/sunrise.exr"
"$tools/dhdr-gbuffer" "$DHDR_SCENE" --size 480x270 --ground-plane \
  --lookat 0.6,0.9,3.6,0.3,0.35,0 -o "$work/g.exr" -q
printf '{"lights": [{"type": "environment", "name": "sky", "image": "sunrise.exr", "rotation": 200}]}\n' \
  >"$work/sky.lights.json"
light() { "$tools/dhdr-light" "$work/g.exr" --scene "$DHDR_SCENE" --lights "$work/sky.lights.json" -q "$@"; }
light --catcher-bounce 0 -o "$work/c0.exr"
light -o "$work/c16.exr"
light --catcher-bounce 256 --denoise off -o "$work/c256.exr"
light --catcher-bounce 256 -o "$work/c256d.exr"
# dhdr's "rotation": 200 is a Mapping node (Point) turning the lookup by -200 degrees.
blender -b --python "$here/cycles_render.py" -- "$work/cycles_1024.exr" -200 1024 0 >"$work/cycles.log"
blender -b --python "$here/cycles_render.py" -- "$work/cy_m200_s64.exr" -200 64 0 >>"$work/cycles.log"
# Debian's python3 (apt's numpy and OpenImageIO), not another one first on PATH.
/usr/bin/python3 "$here/analyze.py" "$work"
