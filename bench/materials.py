#!/usr/bin/env python3
"""Textured materials in dhdr-gbuffer: a 1920x1080 G-buffer of a tiled floor and a sphere whose
material has five maps (base colour, metallic-roughness, normal, occlusion, emissive; 1024²
PNGs, tiled 8 times) against the same scene untextured (trace time from -v, median of 3 runs,
wall time and peak memory); then one 8192² base-colour PNG: load time and peak memory.

    python3 bench/materials.py --bin build/apps [--size 1920x1080]
"""
import argparse
import base64
import json
import math
import os
import re
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lights import run  # noqa: E402


def sphere(rings=64, segments=128):
    """Positions, normals, UVs and indices of a unit sphere at (0, 1, 0)."""
    pos, nor, uv, idx = [], [], [], []
    for r in range(rings + 1):
        t = math.pi * r / rings
        for s in range(segments + 1):
            p = 2 * math.pi * s / segments
            n = (math.sin(t) * math.cos(p), math.cos(t), math.sin(t) * math.sin(p))
            pos += [n[0], n[1] + 1.0, n[2]]
            nor += list(n)
            uv += [4.0 * s / segments, 2.0 * r / rings]
    for r in range(rings):
        for s in range(segments):
            a = r * (segments + 1) + s
            b = a + segments + 1
            idx += [a, b, a + 1, a + 1, b, b + 1]
    return pos, nor, uv, idx


def floor():
    pos = [-6, 0, -6, 6, 0, -6, 6, 0, 6, -6, 0, 6]
    return pos, [0, 1, 0] * 4, [0, 0, 8, 0, 8, 8, 0, 8], [0, 2, 1, 0, 3, 2]


def mesh_document(primitives):
    """A glTF 2.0 document of one mesh in one node whose primitives are `primitives`
    ((positions, normals, UVs, indices) each, flat lists), all of material 0; the caller adds
    "materials" (and its images and textures)."""
    blob, views, accessors, prims = b"", [], [], []
    for pos, nor, uv, idx in primitives:
        attrs = {}
        for name, data, kind, fmt in (("POSITION", pos, "VEC3", "f"), ("NORMAL", nor, "VEC3", "f"),
                                      ("TEXCOORD_0", uv, "VEC2", "f"), (None, idx, "SCALAR", "I")):
            raw = struct.pack("%d%s" % (len(data), fmt), *data)
            views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(raw)})
            blob += raw
            count = len(data) // {"VEC3": 3, "VEC2": 2, "SCALAR": 1}[kind]
            acc = {"bufferView": len(views) - 1, "componentType": 5126 if fmt == "f" else 5125,
                   "count": count, "type": kind}
            if name == "POSITION":
                acc["min"] = [min(pos[i::3]) for i in range(3)]
                acc["max"] = [max(pos[i::3]) for i in range(3)]
            accessors.append(acc)
            if name:
                attrs[name] = len(accessors) - 1
        prims.append({"attributes": attrs, "indices": len(accessors) - 1, "material": 0})
    return {"asset": {"version": "2.0"},
            "buffers": [{"byteLength": len(blob),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
            "bufferViews": views, "accessors": accessors,
            "meshes": [{"primitives": prims}], "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}


def scene(textured):
    """A glTF document: the floor and the sphere, one material, textured or not."""
    material = {"name": "five maps" if textured else "plain",
                "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0.5,
                                         "roughnessFactor": 0.5}}
    doc = mesh_document((floor(), sphere()))
    doc["materials"] = [material]
    if textured:
        names = ["base", "mr", "normal", "ao", "emissive"]
        doc["images"] = [{"uri": n + ".png"} for n in names]
        doc["textures"] = [{"source": i} for i in range(len(names))]
        material["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
        material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {"index": 1}
        material["normalTexture"] = {"index": 2}
        material["occlusionTexture"] = {"index": 3}
        material["emissiveTexture"] = {"index": 4}
        material["emissiveFactor"] = [0.1, 0.1, 0.1]
    return doc


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", default="1920x1080")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="dhdr_materials_")
    tool = os.path.join(args.bin, "dhdr-gbuffer")
    for name, pattern in (("base", "noise:type=uniform:min=0.2:max=0.9"),
                          ("mr", "noise:type=uniform:min=0.3:max=1"),
                          ("normal", "constant:color=0.5,0.5,1"),
                          ("ao", "noise:type=uniform:min=0.5:max=1"),
                          ("emissive", "checker:width=64:height=64")):
        subprocess.run(["oiiotool", "--pattern", pattern, "1024x1024", "3", "-d", "uint8",
                        "-o", os.path.join(work, name + ".png")], check=True)
    print("Textured materials, %s, %d cores" % (args.size, os.cpu_count()))
    traces = {}
    for textured in (False, True):
        path = os.path.join(work, "textured.gltf" if textured else "plain.gltf")
        with open(path, "w") as f:
            json.dump(scene(textured), f)
        runs = []
        for _ in range(3):
            wall, rss, err = run([tool, path, "--lookat", "0,3,7,0,0.8,0", "--size", args.size,
                                  "-o", os.path.join(work, "g.exr"), "-v"])
            trace = float(re.search(r"trace ([0-9.]+) ms", err).group(1))
            runs.append((trace, wall, rss))
        trace = statistics.median(r[0] for r in runs)
        traces[textured] = trace
        print("dhdr-gbuffer %-10s trace %.0f ms (median of 3), wall %.2f s, peak %.0f MiB"
              % ("five maps" if textured else "untextured", trace,
                 statistics.median(r[1] for r in runs), max(r[2] for r in runs)))
    print("trace, textured / untextured: %.2f" % (traces[True] / traces[False]))
    big = os.path.join(work, "big.png")
    subprocess.run(["oiiotool", "--pattern", "checker:width=64:height=64", "8192x8192", "3",
                    "-d", "uint8", "-o", big], check=True)
    doc = scene(True)
    doc["images"] = [{"uri": "big.png"}]
    doc["textures"] = [{"source": 0}]
    for key in ("metallicRoughnessTexture",):
        doc["materials"][0]["pbrMetallicRoughness"].pop(key)
    for key in ("normalTexture", "occlusionTexture", "emissiveTexture"):
        doc["materials"][0].pop(key)
    path = os.path.join(work, "big.gltf")
    with open(path, "w") as f:
        json.dump(doc, f)
    wall, rss, err = run([tool, path, "--lookat", "0,3,7,0,0.8,0", "--size", args.size,
                          "-o", os.path.join(work, "g.exr"), "-v"])
    load = float(re.search(r"load ([0-9.]+) ms", err).group(1))
    print("one 8192x8192 RGB PNG (1 GiB as float RGBA): load %.2f s, wall %.2f s, peak %.0f MiB"
          % (load / 1000, wall, rss))
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
