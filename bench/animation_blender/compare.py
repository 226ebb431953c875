#!/usr/bin/env python3
"""Poses of third-party animated glTF files (Debian's assimp-testmodels: a skin and a morph
cube) in dhdr-gbuffer against Blender's own glTF importer and Cycles' Position pass, frame by
frame: over the pixels that both cover with their whole 3 x 3 neighbourhood, the distance
between the two positions in units of a pixel's footprint (median, 99th percentile, largest),
the pixels that one covers and the other does not, and the motion vectors against Blender's
Vector pass; for contrast the same against the rest
pose (frame 0), which must be far off where the file moves.

    /usr/bin/python3 bench/animation_blender/compare.py --bin build/apps
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

MODELS = "/usr/share/assimp/models/glTF2"
CASES = [
    # name, file, eye, target, frames
    ("simple_skin", MODELS + "/simple_skin/simple_skin.gltf", "0,1,5", "0,1,0", [0, 30, 66, 100, 132]),
    ("AnimatedMorphCube", MODELS + "/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
     "3,2.5,4", "0,0,0", [0, 20, 50, 75, 100]),
]
SIZE, FOV = 160, 39.6


def channels(path, names):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    px = buf.get_pixels(oiio.FLOAT)
    return [px[:, :, spec.channelindex(n)] for n in names]


def interior(covered):
    c = covered.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            c &= np.roll(np.roll(covered, dy, 0), dx, 1)
    c[0, :] = c[-1, :] = c[:, 0] = c[:, -1] = False
    return c


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--blender", default="blender")
    args = ap.parse_args()
    if not os.path.exists(MODELS):
        sys.exit("compare.py: needs Debian's assimp-testmodels (apt-get install assimp-testmodels)")
    here = os.path.dirname(os.path.abspath(__file__))
    work = tempfile.mkdtemp(prefix="dhdr_anim_blender_")
    print("%-18s %5s %7s | %8s %8s %8s | %9s | %-14s | %s" % (
        "file", "frame", "pixels", "median", "p99", "max", "rest max", "coverage p / r",
        "vectors: max difference / max motion (px)"))
    for name, scene, eye, target, frames in CASES:
        e = [float(v) for v in eye.split(",")]
        t = [float(v) for v in target.split(",")]
        for frame in frames:
            ours = os.path.join(work, "%s.%d.gbuf.exr" % (name, frame))
            rest = os.path.join(work, "%s.rest.gbuf.exr" % name)
            theirs = os.path.join(work, "%s.%d.blender.exr" % (name, frame))
            for f, out in ((frame, ours), (0, rest)):
                subprocess.run([os.path.join(args.bin, "dhdr-gbuffer"), scene, "--lookat", eye + "," + target,
                                "--fov", str(FOV), "--size", "%dx%d" % (SIZE, SIZE), "--frame", str(f), "-o", out,
                                "-q"], check=True)
            subprocess.run([args.blender, "-b", "--python", os.path.join(here, "blender_pose.py"), "--", scene,
                            theirs, str(frame), eye, target, str(FOV), "%dx%d" % (SIZE, SIZE)],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            bx, by, bz, ba = channels(theirs, ["ViewLayer.Position.X", "ViewLayer.Position.Y",
                                               "ViewLayer.Position.Z", "ViewLayer.Combined.A"])
            px, py, pz, pa = channels(ours, ["P.X", "P.Y", "P.Z", "A"])
            rx, ry, rz, ra = channels(rest, ["P.X", "P.Y", "P.Z", "A"])
            # Blender is Z-up: glTF's (x, y, z) is Blender's (x, -z, y).
            theirsP = np.stack([bx, bz, -by], -1)
            mask = interior((ba > 0.999) & (pa > 0.999))
            restMask = interior((ba > 0.999) & (ra > 0.999))
            # A pixel's footprint at the point's distance from the eye.
            dist = np.linalg.norm(theirsP - np.array(e), axis=-1)
            foot = dist * 2.0 * math.tan(math.radians(FOV) / 2) / SIZE
            err = np.linalg.norm(np.stack([px, py, pz], -1) - theirsP, axis=-1) / foot
            restErr = np.linalg.norm(np.stack([rx, ry, rz], -1) - theirsP, axis=-1) / foot
            # Motion vectors (Blender's Vector pass, the convention dhdr's motion layer follows):
            # the largest difference in pixels over the same pixels, and the largest motion.
            bv = channels(theirs, ["ViewLayer.Vector." + c for c in "XYZW"])
            ov = channels(ours, ["motion." + c for c in "XYZW"])
            vecErr = max(float(np.abs(o - b)[mask].max()) for o, b in zip(ov, bv))
            vecMax = max(float(np.abs(b)[mask].max()) for b in bv)
            e_ = err[mask]
            # Coverage: pixels one covers whole and the other not at all (a flat skin bending in
            # its own plane keeps every position on that plane; its outline is what moves).
            differs = lambda a: int(np.sum(((ba > 0.999) & (a < 0.001)) | ((ba < 0.001) & (a > 0.999))))
            print("%-18s %5d %7d | %8.3f %8.3f %8.3f | %9.2f | %-14s | %.4f / %.3f" % (
                name, frame, e_.size, np.median(e_), np.percentile(e_, 99), e_.max(),
                restErr[restMask].max() if restMask.any() else float("nan"),
                "%d / %d" % (differs(pa), differs(ra)), vecErr, vecMax))
    print("(positions in pixels of footprint; Cycles averages 16 positions over each pixel, dhdr takes its centre)")


if __name__ == "__main__":
    main()
