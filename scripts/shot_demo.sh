#!/usr/bin/env bash
# The animated shot on the farm (docs/animation.md, "A shot on the farm"): dhdr-farm runs
# docs/examples/shot.farm.json (testdata/shot.gltf through gbuffer -> light -> aa -> motionblur
# -> bloom -> tonemap with eye adaptation) over frames 1-24 as local processes, into out/shot/
# (the pipeline file names its outputs). Then writes
#   OUT/shot_sheet.png  the 24 frames, 6 x 4
#   OUT/shot_blur.png   frame 10 without | with motion blur, at the frame's adapted exposure
#                       (the lower middle, twice as large)
# With --docs also docs/images/shot_sheet.png and docs/images/shot_blur.png (what the README
# and docs/animation.md show).
# Usage: scripts/shot_demo.sh TOOLS_DIR OUT_DIR [--docs]   (make demo passes build/apps out/demo)
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
docs=${3:-}
here=$(cd "$(dirname "$0")/.." && pwd)
tools=$(cd "$tools" && pwd)
pipeline="$here/docs/examples/shot.farm.json"
frames=out/shot # the pipeline's output folder, relative to the repository
state="$out/shot.farm"
mkdir -p "$out"
step() { echo "== $*"; "$@"; }

# A fresh render every time: the farm would skip frames left by an earlier build.
rm -rf "${here:?}/$frames" "$state"
start=$(date +%s.%N)
step "$tools/dhdr-farm" submit "$pipeline" --frames 1-24 --chunk 8 --engine local -j 2 \
  --bin "$tools" --state "$state"
end=$(date +%s.%N)
took=$(python3 -c "print(round($end - $start, 1))")
echo "== the shot (24 frames, 320x240, 6 stages) took $took s"

# The contact sheet: the final PNGs in frame order, alpha dropped (the background outside the
# box is black, as the frames show it).
sheet=()
for f in $(seq -f %04g 1 24); do sheet+=("$here/$frames/shot.$f.png"); done
echo "== oiiotool $frames/shot.{0001..0024}.png --mosaic:pad=2 6x4 --ch R,G,B" \
  "-o $out/shot_sheet.png"
oiiotool "${sheet[@]}" --mosaic:pad=2 6x4 --ch R,G,B -o "$out/shot_sheet.png"

# Frame 10 (the elbow bends 9 degrees a frame, the block turns 3.75) without motion blur: the
# same chain from dhdr-aa's output, bloomed and mapped with the exposure the eye had adapted
# to at frame 10 (the farm's scanned statistics), beside the farm's own frame 10; the lower
# middle of both, where the arm and the blocks move, twice as large.
step "$tools/dhdr-bloom" "$here/$frames/shot.aa.0010.exr" -o "$out/shot.sharp.0010.exr" -q
step "$tools/dhdr-tonemap" "$out/shot.sharp.####.exr" --frames 10-10 \
  --adapt-from "$state/stats/tonemap.adapted.json" -o "$out/shot.sharp.####.png" -q
crop=(--ch R,G,B --cut 160x120+70+100 --resize:filter=box 320x240)
step oiiotool "$out/shot.sharp.0010.png" "${crop[@]}" "$here/$frames/shot.0010.png" "${crop[@]}" \
  --mosaic:pad=2 2x1 -o "$out/shot_blur.png"

if [ "$docs" = "--docs" ]; then
  # Half size for the README: the sheet 960 pixels wide.
  step oiiotool "$out/shot_sheet.png" --resize 50% -o "$here/docs/images/shot_sheet.png"
  step cp "$out/shot_blur.png" "$here/docs/images/shot_blur.png"
fi
