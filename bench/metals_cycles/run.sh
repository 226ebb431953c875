#!/usr/bin/env bash
# dhdr's image-based lighting of rough metals against Blender Cycles (issue 22; README.md here).
# Five spheres (roughness 0, 0.25, 0.5, 0.75, 1) in a row, no floor, frontal camera, 400x120,
# lit by an HDRI only: Poly Haven's forest and sunrise (blender-data) and the analytic sky with a
# small sun of scripts/ibl_demo.sh; and a white furnace (uniform sky of 1). Materials: copper (0.95, 0.64, 0.54, metallic 1), neutral
# (0.9, metallic 1), and white (0.8, metallic 0, --diffuse burley) to check units on a diffuse
# surface. dhdr: dhdr-ibl defaults (sun split off), no --scene (spheres see the whole sky, not
# each other), --env-specular split-sum / quadrature / auto, plus the split-off sun alone (to
# mark sun-dominated pixels), and auto with the sun kept in the sky (dhdr-ibl --sun-threshold 0). Cycles: the HDRI as world at strength 1, Multiscatter GGX, the
# spheres visible to camera rays only, 2 x SAMPLES/2 samples with two seeds (their difference is
# Cycles' noise). Renders run one at a time, 2 threads.
# Usage: bench/metals_cycles/run.sh [TOOLS_DIR] [WORK_DIR] [SAMPLES] [MATERIALS] [HDRIS]
set -euo pipefail
tools=${1:-build/apps}
work=${2:-/tmp/metals_cycles}
spp=${3:-512}
mats=${4:-"white copper neutral"}
hdris=${5:-"forest sunrise sky furnace"}
here=$(cd "$(dirname "$0")" && pwd)
studio=/usr/share/blender/datafiles/studiolights/world
mkdir -p "$work"; cd "$work"
W=400 H=120 EYE=0,0,6 TGT=0,0,0 FOV=10.5
declare -A COL=([copper]=0.95,0.64,0.54 [neutral]=0.9,0.9,0.9 [white]=0.8,0.8,0.8)
declare -A MET=([copper]=1 [neutral]=1 [white]=0)
for h in $hdris; do
  if [ "$h" = furnace ]; then   # a uniform white sky: each BSDF's directional albedo, no lighting detail
    [ -f furnace.exr ] || oiiotool --pattern constant:color=1,1,1 512x256 3 -d float -o furnace.exr
  elif [ "$h" = sky ]; then   # scripts/ibl_demo.sh's sky: gradient, darker ground, a 12-texel sun of 30,000
    [ -f sky.exr ] || oiiotool --pattern fill:top=0.35,0.55,1.0:bottom=0.9,0.9,0.95 2048x512 3 \
      --pattern fill:top=0.25,0.22,0.2:bottom=0.12,0.1,0.09 2048x512 3 --mosaic 1x2 \
      --box:color=30000,28000,24000:fill=1 1530,230,1542,242 -d float -o sky.exr
  else
    cp -f "$studio/$h.exr" "$h.exr"
  fi
  "$tools/dhdr-ibl" "$h.exr" -o "$h.ibl.exr" --threads 2 -v 2>&1 | grep sun || true
  printf '{"lights": [{"type": "environment", "name": "env", "image": "%s.ibl.exr"}]}\n' "$h" >"$h.json"
  # diagnosis: the same bake with the sun kept in the sky (no directional sun)
  "$tools/dhdr-ibl" "$h.exr" -o "$h.sunkept.ibl.exr" --sun-threshold 0 --threads 2 -q
  printf '{"lights": [{"type": "environment", "name": "env", "image": "%s.sunkept.ibl.exr"}]}\n' "$h" >"$h.sunkept.json"
  # the split-off sun alone, as dhdr-light adds it: a directional light of the bake's illuminance and angle
  /usr/bin/python3 - "$h.ibl.exr" >"${h}_sun.json" <<'PY'
import OpenImageIO as oiio, sys, math, json
s = oiio.ImageInput.open(sys.argv[1]).spec()
if s.getattribute("dhdr:sunDirection") is None:   # no sun: a black one
    print(json.dumps({"lights": [{"type": "directional", "name": "sun", "direction": [0, -1, 0], "color": [0, 0, 0]}]})); sys.exit()
d = [-x for x in s.getattribute("dhdr:sunDirection")]
print(json.dumps({"lights": [{"type": "directional", "name": "sun", "direction": d, "intensity": 1,
    "color": list(s.getattribute("dhdr:sunIlluminance")), "angle": math.degrees(s.getattribute("dhdr:sunAngle"))}]}))
PY
done
for m in $mats; do
  /usr/bin/python3 "$here/make_scene.py" "$m.gltf" "${COL[$m]}" "${MET[$m]}"
  "$tools/dhdr-gbuffer" "$m.gltf" --size ${W}x${H} --lookat $EYE,$TGT --fov $FOV --threads 2 -q -o "g_$m.exr"
  extra=(); [ "$m" = white ] && extra=(--diffuse burley)
  for h in $hdris; do
    for mode in split-sum quadrature auto; do
      "$tools/dhdr-light" "g_$m.exr" --lights "$h.json" --env-specular $mode "${extra[@]}" \
        --type float --threads 2 -q -o "d_${m}_${h}_$mode.exr"
    done
    "$tools/dhdr-light" "g_$m.exr" --lights "$h.sunkept.json" "${extra[@]}" --type float --threads 2 -q -o "d_${m}_${h}_auto-sunkept.exr"
    "$tools/dhdr-light" "g_$m.exr" --lights "${h}_sun.json" "${extra[@]}" --type float --threads 2 -q -o "d_${m}_${h}_sun.exr"
    for seed in 1 2; do
      [ -f "cy_${m}_${h}_s$seed.exr" ] && continue
      blender -b --python "$here/cycles_render.py" -- "$m.gltf" "$work/cy_${m}_${h}_s$seed.exr" "$work/$h.exr" \
        $((spp / 2)) $seed $W $H $EYE $TGT $FOV >"cycles_${m}_${h}_s$seed.log" 2>&1
    done
  done
done
for m in $mats; do
  for h in $hdris; do
    # Debian's python3 (apt's numpy and OpenImageIO), not another one first on PATH.
    /usr/bin/python3 "$here/analyze.py" "$work" $m $h "$work/side_${m}_$h.png"
  done
done
/usr/bin/python3 "$here/summary.py" "$work" >"$work/summary.md"
for m in $mats; do [ "$m" = white ] || /usr/bin/python3 "$here/diag_mirror.py" "$work" $m $hdris; done   # metals only (F = F0)
case " $mats " in *" copper "*) case " $hdris " in *" forest "*)
  /usr/bin/python3 "$here/modes.py" "$work" copper forest "$work/modes_copper_forest.png";; esac;; esac
# Diagnosis: one directional light (the generated sky's sun direction, angle 0, E = 1) and no world, to take
# the BRDF apart (diag_sun.py): dhdr against Cycles' Multiscatter GGX and single-scatter GGX, 128 spp.
D=0.001,-0.748,-0.664
printf '{"lights": [{"type": "directional", "name": "sun", "direction": [%s], "intensity": 1}]}\n' $D >pointsun.json
for m in $mats; do
  [ "$m" = white ] && continue
  "$tools/dhdr-light" "g_$m.exr" --lights pointsun.json --type float --threads 2 -q -o "d_${m}_pointsun.exr"
  for dist in MULTI_GGX GGX; do
    [ -f "cysun_${m}_$dist.exr" ] || DHDR_CYCLES_SUN=$D DHDR_CYCLES_DISTRIBUTION=$dist blender -b --python "$here/cycles_render.py" -- \
      "$m.gltf" "$work/cysun_${m}_$dist.exr" "$work/${hdris%% *}.exr" 128 1 $W $H $EYE $TGT $FOV >"cysun_${m}_$dist.log" 2>&1
  done
  /usr/bin/python3 "$here/diag_sun.py" "$work" $m
done
