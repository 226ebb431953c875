#!/usr/bin/env python3
"""Writes sheen_spheres.gltf (to the folder given, else testdata/): two rows of five spheres of
radius 0.2 m on a dark red velvet-like base (roughness 0.8), each with KHR_materials_sheen --
the top row a white sheen of colour 0, 0.25, 0.5, 0.75, 1 at sheenRoughness 0.5, the bottom row
colour 1 at sheenRoughness 0.1, 0.3, 0.5, 0.7, 1 -- and a camera looking at them, for
docs/images/sheen.png (docs/scenes.md) and python/tests/test_scene.py."""
import base64
import json
import math
import os
import struct
import sys

RADIUS = 0.2
BASE = {"baseColorFactor": [0.30, 0.02, 0.05, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8}
# (sheen colour, sheen roughness) per sphere, top row then bottom row, left to right.
TOP = [(c, 0.5) for c in (0.0, 0.25, 0.5, 0.75, 1.0)]
BOTTOM = [(1.0, r) for r in (0.1, 0.3, 0.5, 0.7, 1.0)]


def uv_sphere(cx, cy, cz, r, rings=32, segments=64):
    positions, normals, indices = [], [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            normals.append(n)
            positions.append((cx + r * n[0], cy + r * n[1], cz + r * n[2]))
    for i in range(rings):
        for j in range(segments):
            a = i * (segments + 1) + j
            b = a + segments + 1
            indices += [a, a + 1, b, a + 1, b + 1, b]  # counter-clockwise seen from outside
    return positions, normals, indices


def material(k, colour, roughness):
    return {"name": "sheen_%d" % k, "pbrMetallicRoughness": BASE,
            "extensions": {"KHR_materials_sheen": {
                "sheenColorFactor": [colour] * 3, "sheenRoughnessFactor": roughness}}}


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    blob = bytearray()
    views, accessors, meshes, nodes, materials = [], [], [], [], []

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(views) - 1

    for k, (colour, roughness) in enumerate(TOP + BOTTOM):
        x, y = -1.0 + 0.5 * (k % 5), 0.25 if k < 5 else -0.25
        positions, normals, indices = uv_sphere(x, y, 0.0, RADIUS)
        pv = add_view(b"".join(struct.pack("<3f", *p) for p in positions), 34962)
        nv = add_view(b"".join(struct.pack("<3f", *n) for n in normals), 34962)
        iv = add_view(struct.pack("<%dH" % len(indices), *indices), 34963)
        lo = [min(p[i] for p in positions) for i in range(3)]
        hi = [max(p[i] for p in positions) for i in range(3)]
        accessors += [{"bufferView": pv, "componentType": 5126, "count": len(positions), "type": "VEC3",
                       "min": lo, "max": hi},
                      {"bufferView": nv, "componentType": 5126, "count": len(normals), "type": "VEC3"},
                      {"bufferView": iv, "componentType": 5123, "count": len(indices), "type": "SCALAR"}]
        a = len(accessors)
        meshes.append({"name": "sphere_%d" % k, "primitives": [{
            "attributes": {"POSITION": a - 3, "NORMAL": a - 2}, "indices": a - 1, "material": k}]})
        nodes.append({"name": "sphere_%d" % k, "mesh": k})
        materials.append(material(k, colour, roughness))
    nodes.append({"name": "camera", "camera": 0, "translation": [0.0, 0.0, 3.2]})
    gltf = {
        "asset": {"version": "2.0", "generator": "dhdr testdata/make_sheen_spheres.py"},
        "extensionsUsed": ["KHR_materials_sheen"],
        "scene": 0,
        "scenes": [{"name": "sheen_spheres", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": [{"name": "camera", "type": "perspective",
                     "perspective": {"yfov": 0.4, "aspectRatio": 2.0, "znear": 0.01, "zfar": 100.0}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
    }
    with open(os.path.join(out, "sheen_spheres.gltf"), "w") as f:
        json.dump(gltf, f)
        f.write("\n")


if __name__ == "__main__":
    main()
