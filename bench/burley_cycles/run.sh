#!/usr/bin/env bash
# dhdr's --diffuse burley (and lambert) against Blender Cycles' Principled BSDF diffuse, direct
# light only (bench/burley_cycles/README.md): three white 0.8 dielectric spheres of roughness 0,
# 0.5, 1 on a grey roughness-1 floor under one sun of 3 W/m^2 and angle 0, no world light, 360x160.
# dhdr: diffuse layer = frame - frame of the same scene with black base colours (specular only),
# hard shadows from --scene. Cycles: DiffDir x DiffCol, max bounces 0, 128 samples, box filter.
# Three suns: back (behind the camera: retro-reflection), side, rim (high, from behind the spheres: l.v < 0).
# Needs apt packages blender (3.4) and python3-openimageio. Renders run one at a time, 2 threads.
# Usage: bench/burley_cycles/run.sh [TOOLS_DIR] [WORK_DIR] [SAMPLES]
set -euo pipefail
tools=${1:-build/apps}
work=${2:-/tmp/burley_cycles}
spp=${3:-128}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$work"
W=360 H=160 EYE=0,0.45,3.0 TGT=0,0.3,0 FOV=17 E=3
/usr/bin/python3 "$here/make_scene.py" "$work/scene.gltf"
/usr/bin/python3 "$here/make_scene.py" "$work/black.gltf" black
declare -A SUN=([back]=0.3,-0.5,-1 [side]=-1,-0.3,0.1 [rim]=0.25,-0.9,0.5)
for cfg in back side rim; do
  d=${SUN[$cfg]}
  "$tools/dhdr-gbuffer" "$work/scene.gltf" --size ${W}x${H} --lookat $EYE,$TGT --fov $FOV --threads 2 -q -o "$work/g_$cfg.exr"
  "$tools/dhdr-gbuffer" "$work/black.gltf" --size ${W}x${H} --lookat $EYE,$TGT --fov $FOV --threads 2 -q -o "$work/gk_$cfg.exr"
  printf '{"lights": [{"type": "directional", "name": "sun", "direction": [%s], "intensity": %s}]}\n' \
    "$d" "$((E * 683))" >"$work/sun_$cfg.json"          # E W/m^2 * 683 lm/W, --radiometric undoes it
  light() { "$tools/dhdr-light" "$1" --scene "$2" --lights "$work/sun_$cfg.json" --radiometric \
    --specular-samples 0 --env-samples 0 --threads 2 --type float -q -o "$3" "${@:4}"; }
  light "$work/g_$cfg.exr" "$work/scene.gltf" "$work/d_${cfg}_burley.exr" --diffuse burley
  light "$work/g_$cfg.exr" "$work/scene.gltf" "$work/d_${cfg}_lambert.exr" --diffuse lambert
  light "$work/gk_$cfg.exr" "$work/black.gltf" "$work/d_${cfg}_spec.exr"
  blender -b --python "$here/cycles_render.py" -- "$work/scene.gltf" "$work/cy_$cfg.exr" "$d" $E "$spp" \
    $W $H $EYE $TGT $FOV >"$work/cycles_$cfg.log" 2>&1
done
for cfg in back side rim; do
  # Debian's python3 (apt's numpy and OpenImageIO), not another one first on PATH.
  /usr/bin/python3 "$here/analyze.py" "$work" $cfg "${SUN[$cfg]}" $E
done
