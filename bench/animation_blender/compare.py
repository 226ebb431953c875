#!/usr/bin/env python3
"""Poses of third-party animated glTF files (Debian's assimp-testmodels: a skin, a morph cube,
and Khronos' 2CylinderEngine given a rigid animation here, every one of its 67 meshes moving as
a whole) in dhdr-gbuffer against Blender's own glTF importer and Cycles' Position pass, frame by
frame: over the pixels that both cover with their whole 3 x 3 neighbourhood, the distance
between the two positions in units of a pixel's footprint (median, 99th percentile, largest),
the pixels that one covers and the other does not, and the motion vectors against Blender's
Vector pass; for contrast the same against the rest
pose (frame 0), which must be far off where the file moves.

    /usr/bin/python3 bench/animation_blender/compare.py --bin build/apps
"""
import argparse
import base64
import json
import math
import os
import struct
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

MODELS = "/usr/share/assimp/models/glTF2"
ENGINE = MODELS + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"


def animated_engine(work):
    """Khronos' 2CylinderEngine (67 meshes) made to move rigidly, written here as a .gltf: its
    scene's roots under a new node, scaled to 1/100, that turns 90 degrees about Y and slides
    +x 1 unit over 2 s, and one part under a node of its own that rises 0.5 units meanwhile.
    Every mesh moves as a whole, so dhdr traces each as an Embree instance."""
    with open(ENGINE, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2
    jlen, jtype = struct.unpack_from("<II", data, 12)
    doc = json.loads(data[20:20 + jlen])
    blen, btype = struct.unpack_from("<II", data, 20 + jlen)
    with open(os.path.join(work, "engine.bin"), "wb") as f:
        f.write(data[28 + jlen:28 + jlen + blen])
    doc["buffers"][0]["uri"] = "engine.bin"
    times = [0.0, 1.0, 2.0]
    # About Y: 0, 45 and 90 degrees (x, y, z, w).
    turn = []
    for degrees in (0.0, 45.0, 90.0):
        h = math.radians(degrees) / 2
        turn += [0.0, math.sin(h), 0.0, math.cos(h)]
    slide = [0, 0, 0, 0.5, 0, 0, 1, 0, 0]
    roots = doc["scenes"][doc.get("scene", 0)]["nodes"]
    # One part of the engine, wrapped in a node of its own (its nodes are given by matrices,
    # which glTF does not animate), rises 0.5 units (50 of the file's) while the rest turns.
    parent = next(n for n in roots if doc["nodes"][n].get("children"))
    part = doc["nodes"][parent]["children"][0]
    doc["nodes"].append({"name": "lifter", "children": [part]})
    riser = len(doc["nodes"]) - 1
    doc["nodes"][parent]["children"][0] = riser
    rise = [0, 0, 0, 0, 25, 0, 0, 50, 0]
    blobs = [struct.pack("<3f", *times), struct.pack("<12f", *turn), struct.pack("<9f", *slide),
             struct.pack("<9f", *rise)]
    payload = b"".join(blobs)
    doc["buffers"].append({"byteLength": len(payload),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(payload).decode()})
    offset = 0
    accessors = []
    for blob, (kind, count) in zip(blobs, [("SCALAR", 3), ("VEC4", 3), ("VEC3", 3), ("VEC3", 3)]):
        doc["bufferViews"].append({"buffer": len(doc["buffers"]) - 1, "byteOffset": offset,
                                   "byteLength": len(blob)})
        accessor = {"bufferView": len(doc["bufferViews"]) - 1, "componentType": 5126, "count": count,
                    "type": kind}
        if kind == "SCALAR":
            accessor.update({"min": [0.0], "max": [2.0]})
        doc["accessors"].append(accessor)
        accessors.append(len(doc["accessors"]) - 1)
        offset += len(blob)
    doc["nodes"].append({"name": "mover", "children": roots, "scale": [0.01, 0.01, 0.01]})
    mover = len(doc["nodes"]) - 1
    doc["scenes"][doc.get("scene", 0)]["nodes"] = [mover]
    samplers = [{"input": accessors[0], "output": accessors[i]} for i in (1, 2, 3)]
    channels = [{"sampler": 0, "target": {"node": mover, "path": "rotation"}},
                {"sampler": 1, "target": {"node": mover, "path": "translation"}}]
    channels.append({"sampler": 2, "target": {"node": riser, "path": "translation"}})
    doc["animations"] = [{"name": "rigid", "samplers": samplers, "channels": channels}]
    # The file's own camera would be framed for the unscaled engine: compare.py sets its own.
    path = os.path.join(work, "engine_rigid.gltf")
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


CASES = [
    # name, file, eye, target, frames
    ("simple_skin", MODELS + "/simple_skin/simple_skin.gltf", "0,1,5", "0,1,0", [0, 30, 66, 100, 132]),
    ("AnimatedMorphCube", MODELS + "/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
     "3,2.5,4", "0,0,0", [0, 20, 50, 75, 100]),
    ("2CylinderEngine", None, "7,5,7", "0.5,0,0", [0, 6, 12, 24, 36, 48]),
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
    print("%-18s %5s %7s | %8s %8s %8s | %9s | %-14s | %s | %s" % (
        "file", "frame", "pixels", "median", "p99", "max", "rest max", "coverage p / r",
        "vectors: max difference / max motion (px)", "away from depth edges"))
    for name, scene, eye, target, frames in CASES:
        scene = scene or animated_engine(work)
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
            # The same away from depth edges (dhdr's P within 3 footprints over the 3 x 3
            # neighbourhood), where Cycles' 16 samples do not average two surfaces' motions.
            ours3 = np.stack([px, py, pz], -1)
            jump = np.zeros_like(foot)
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    moved = np.roll(np.roll(ours3, dy, 0), dx, 1)
                    jump = np.maximum(jump, np.linalg.norm(moved - ours3, axis=-1) / foot)
            smooth = mask & (jump < 3)
            vecSmooth = max(float(np.abs(o - b)[smooth].max()) for o, b in zip(ov, bv))
            vecMax = max(float(np.abs(b)[mask].max()) for b in bv)
            e_ = err[mask]
            # Coverage: pixels one covers whole and the other not at all (a flat skin bending in
            # its own plane keeps every position on that plane; its outline is what moves).
            differs = lambda a: int(np.sum(((ba > 0.999) & (a < 0.001)) | ((ba < 0.001) & (a > 0.999))))
            print("%-18s %5d %7d | %8.3f %8.3f %8.3f | %9.2f | %-14s | %.4f / %.3f | %.4f" % (
                name, frame, e_.size, np.median(e_), np.percentile(e_, 99), e_.max(),
                restErr[restMask].max() if restMask.any() else float("nan"),
                "%d / %d" % (differs(pa), differs(ra)), vecErr, vecMax, vecSmooth))
    print("(positions in pixels of footprint; Cycles averages 16 positions over each pixel, dhdr takes its centre)")


if __name__ == "__main__":
    main()
