#!/bin/sh
# bench/transmission_cycles/run.sh [TOOLS_DIR] [WORK_DIR] [SAMPLES] [HDRI] [SUN_E]: thin glass panes
# (KHR_materials_transmission) built in Blender 3.4, exported by its glTF exporter and rendered
# by Cycles (cycles_scene.py), then lit by dhdr from the exported .glb with the same sun and
# HDRI, and compared per region (analyze.py). README.md says what is measured and why.
set -e
HERE=$(cd "$(dirname "$0")" && pwd)
TOOLS=$(cd "${1:-$HERE/../../build/apps}" && pwd)
WORK=${2:-/tmp/transmission_cycles}
SAMPLES=${3:-384}
HDRI=${4:-/usr/share/blender/datafiles/studiolights/world/forest.exr}
SUN_E=${5:-5}
mkdir -p "$WORK"
# Blender builds and exports the scene (scene.glb) and renders it; its render is kept and reused.
[ -f "$WORK/cycles.exr" ] || blender -b --python "$HERE/cycles_scene.py" -- \
    "$WORK" "$HDRI" "$SAMPLES" 320 240 "$SUN_E" > "$WORK/blender.log" 2>&1
"$TOOLS/dhdr-ibl" "$HDRI" -o "$WORK/sky.ibl.exr"
# The sun: SUN_E W/m^2 as lux (x 683, undone by --radiometric), travelling along Blender's
# (0.35, 0.8, -1) = glTF's (0.35, -1, -0.8).
printf '{"lights": [{"type": "environment", "image": "sky.ibl.exr"}, {"type": "directional", "name": "sun", "direction": [0.35, -1.0, -0.8], "intensity": %s}]}\n' \
    "$(awk "BEGIN { print $SUN_E * 683 }")" > "$WORK/lights.json"
CAM="--lookat 0,2.0,4.5,0,0.45,-1.2 --fov 40 --size 320x240 --threads 2 -q"
"$TOOLS/dhdr-gbuffer" "$WORK/scene.glb" $CAM -o "$WORK/g.exr"
"$TOOLS/dhdr-gbuffer" "$WORK/scene.glb" $CAM --flat -o "$WORK/g_flat.exr"     # ids only
(cd "$WORK" && "$TOOLS/dhdr-light" g.exr --scene scene.glb --lights lights.json --radiometric \
    --gi direct --diffuse burley --env-samples 64 --threads 2 --type float --background env -q \
    --deep-out dhdr.deep.exr -o dhdr.exr)
printf '{"lights": [{"type": "directional", "name": "sun", "direction": [0.35, -1.0, -0.8], "intensity": %s}]}\n' \
    "$(awk "BEGIN { print $SUN_E * 683 }")" > "$WORK/sun.json"
(cd "$WORK" && "$TOOLS/dhdr-light" g.exr --scene scene.glb --lights sun.json --radiometric \
    --gi direct --diffuse burley --threads 2 --type float -q -o dhdr_sun.exr)
# Cycles' variants for the shadows (README.md), 128 samples each, kept and reused.
for v in ${VARIANTS-opaquepanes sunonly}; do
  [ -f "$WORK/cycles_$v.exr" ] || blender -b --python "$HERE/cycles_scene.py" -- \
      "$WORK" "$HDRI" 128 320 240 "$SUN_E" $v > "$WORK/blender_$v.log" 2>&1
done
/usr/bin/python3 "$HERE/analyze.py" "$WORK"
