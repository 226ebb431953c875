#!/usr/bin/env bash
# Motion blur in post (docs/tonemap.md, "Motion blur"; docs/animation.md): the animated Cornell
# box (testdata/cornell_animated.gltf: the camera pans, the short block moves) at 1 s, its
# motion vectors taken one second apart (--fps 1) so that the blur is long enough to see, lit,
# then dhdr-motionblur with a shutter of one frame, both tone-mapped alike. Writes
# OUT/motion_blur.png: without | with.
# Usage: scripts/motionblur_demo.sh TOOLS_DIR OUT_DIR   (make demo passes build/apps out/demo)
set -euo pipefail
tools=${1:-build/apps}
out=${2:-out/demo}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
step() { echo "== $*"; "$@"; }
step "$tools/dhdr-gbuffer" "$here/testdata/cornell_animated.gltf" --size 480x480 --fps 1 --frame 1 \
  -o "$out/mb.gbuf.exr" -q
step "$tools/dhdr-light" "$out/mb.gbuf.exr" --lights "$here/testdata/cornell_box.lights.json" \
  -o "$out/mb.hdr.exr" -q
step "$tools/dhdr-motionblur" "$out/mb.hdr.exr" --gbuffer "$out/mb.gbuf.exr" --shutter 1 \
  -o "$out/mb.blurred.exr" -v
# One exposure for both: the blurred frame's own metering would differ a little.
step "$tools/dhdr-tonemap" "$out/mb.hdr.exr" -o "$out/mb.sharp.png" -q --op exposure --exposure -1.5
step "$tools/dhdr-tonemap" "$out/mb.blurred.exr" -o "$out/mb.blurred.png" -q --op exposure --exposure -1.5
step oiiotool "$out/mb.sharp.png" "$out/mb.blurred.png" --mosaic 2x1 -o "$out/motion_blur.png"
