#!/usr/bin/env python3
"""Writes testdata/spheres.gltf: three spheres of radius 0.25 m standing on the plane y = 0
(no floor: dhdr-gbuffer --ground-plane adds the shadow catcher) -- polished gold, a glossy red
dielectric and a rough white one -- and a camera looking at them, for the IBL demo
(scripts/ibl_demo.sh, docs/ibl.md)."""
import base64
import json
import math
import os
import struct

RADIUS = 0.25
SPHERES = [  # centre x, z; material
    (-0.6, 0.0, "gold"), (0.0, 0.15, "red"), (0.6, 0.0, "white")]
MATERIALS = {
    "gold": {"baseColorFactor": [1.0, 0.78, 0.34, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.15},
    "red": {"baseColorFactor": [0.7, 0.05, 0.04, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.3},
    "white": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.9},
}


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
            # Counter-clockwise seen from outside.
            indices += [a, a + 1, b, a + 1, b + 1, b]
    return positions, normals, indices


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    blob = bytearray()
    views, accessors, meshes, nodes = [], [], [], []

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(views) - 1

    names = list(MATERIALS)
    for k, (x, z, material) in enumerate(SPHERES):
        positions, normals, indices = uv_sphere(x, RADIUS, z, RADIUS)
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
        meshes.append({"name": material + "_sphere", "primitives": [{
            "attributes": {"POSITION": a - 3, "NORMAL": a - 2}, "indices": a - 1,
            "material": names.index(material)}]})
        nodes.append({"name": material + "_sphere", "mesh": k})
    materials = [{"name": n, "pbrMetallicRoughness": m} for n, m in MATERIALS.items()]
    # The camera at (0, 0.7, 2.4) looking at (0, 0.2, 0): pitched down by atan(0.5 / 2.4).
    pitch = -math.atan2(0.5, 2.4)
    nodes.append({"name": "camera", "camera": 0, "translation": [0.0, 0.7, 2.4],
                  "rotation": [math.sin(pitch / 2), 0.0, 0.0, math.cos(pitch / 2)]})
    gltf = {
        "asset": {"version": "2.0", "generator": "dhdr testdata/make_spheres.py"},
        "scene": 0,
        "scenes": [{"name": "spheres", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": [{"name": "camera", "type": "perspective",
                     "perspective": {"yfov": 0.6, "aspectRatio": 16 / 9, "znear": 0.01, "zfar": 100.0}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
    }
    with open(os.path.join(here, "spheres.gltf"), "w") as f:
        json.dump(gltf, f)
        f.write("\n")


if __name__ == "__main__":
    main()
