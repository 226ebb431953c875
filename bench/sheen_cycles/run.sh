#!/bin/sh
# bench/sheen_cycles/run.sh [TOOLS_DIR] [WORK_DIR] [SAMPLES] [HDRI]: the sheen spheres of
# testdata/make_sheen_spheres.py under an HDRI, by dhdr (no --scene: each sphere sees the whole
# sky) and by Blender 3.4's Cycles after its glTF import (README.md), then analyze.py.
set -e
HERE=$(cd "$(dirname "$0")" && pwd)
TOOLS=${1:-$HERE/../../build/apps}
WORK=${2:-/tmp/sheen_cycles}
SAMPLES=${3:-128}
HDRI=${4:-/usr/share/blender/datafiles/studiolights/world/forest.exr}
mkdir -p "$WORK"
python3 "$HERE/../../testdata/make_sheen_spheres.py" "$WORK"
"$TOOLS/dhdr-ibl" "$HDRI" -o "$WORK/sky.ibl.exr"
echo '{"lights": [{"type": "environment", "image": "sky.ibl.exr"}]}' > "$WORK/sky.json"
"$TOOLS/dhdr-gbuffer" "$WORK/sheen_spheres.gltf" --size 480x240 -o "$WORK/g.exr"
(cd "$WORK" && "$TOOLS/dhdr-light" g.exr --lights sky.json --type float -o dhdr.exr)
[ -f "$WORK/cycles.exr" ] || blender -b --python "$HERE/cycles_render.py" -- \
    "$WORK/sheen_spheres.gltf" "$WORK/cycles.exr" "$HDRI" "$SAMPLES" 480 240 0,0,3.2 0,0,0 22.918312 \
    > "$WORK/blender.log" 2>&1
/usr/bin/python3 "$HERE/analyze.py" "$WORK/g.exr" "$WORK/dhdr.exr" "$WORK/cycles.exr"
