#!/usr/bin/env python3
"""Writes testdata/cornell_box.gltf and testdata/cornell_box.lights.json.

Geometry is the Cornell box as published by the Cornell Program of Computer Graphics
(millimetres there, metres here). Reflectances are the usual RGB reductions of the
measured spectra. The camera is the published one: at (278, 273, -800) mm looking down +z,
35 mm focal length on a 25 mm square film, so yfov = 2 atan(12.5 / 35).
"""
import base64
import json
import math
import os
import struct

MM = 0.001

# name: (material, list of quads; each quad listed as published, counter-clockwise or not)
QUADS = {
    "floor": ("white", [[(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]]),
    "ceiling": ("white", [[(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]]),
    "back_wall": ("white", [[(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]]),
    "right_wall": ("green", [[(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]]),
    "left_wall": ("red", [[(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]]),
    "light": ("light", [[(343.0, 548.7, 227.0), (343.0, 548.7, 332.0), (213.0, 548.7, 332.0), (213.0, 548.7, 227.0)]]),
    "short_block": ("white", [
        [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)],
        [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)],
        [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)],
        [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)],
        [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)],
    ]),
    "tall_block": ("white", [
        [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)],
        [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)],
        [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)],
        [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)],
        [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)],
    ]),
}

MATERIALS = {
    "white": {"baseColorFactor": [0.725, 0.71, 0.68, 1.0]},
    "red": {"baseColorFactor": [0.63, 0.065, 0.05, 1.0]},
    "green": {"baseColorFactor": [0.14, 0.45, 0.091, 1.0]},
    # Radiance (17, 12, 4) as in the usual RGB Cornell box: factor x strength.
    "light": {"baseColorFactor": [0.78, 0.78, 0.78, 1.0], "emissive": [1.0, 12.0 / 17.0, 4.0 / 17.0], "strength": 17.0},
}

SPOT_POSITION = (0.10, 0.45, 0.05)
SPOT_DIRECTION = (0.35, -0.6, 0.72)

CENTRE = (0.5 * (556.0 + 0.0) * MM, 0.5 * 548.8 * MM, 0.5 * 559.2 * MM)


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def face_normal(quad):
    """Unit normal of a quad, oriented toward the inside of the room (or out of a block)."""
    n = normalize(cross(sub(quad[1], quad[0]), sub(quad[2], quad[0])))
    return n


def mesh_arrays(name, quads):
    positions, normals, indices = [], [], []
    block_centre = None
    if name.endswith("block"):
        pts = [p for q in quads for p in q]
        block_centre = tuple(sum(p[i] for p in pts) / len(pts) * MM for i in range(3))
    for quad in quads:
        q = [tuple(c * MM for c in p) for p in quad]
        n = face_normal(q)
        centre = tuple(sum(p[i] for p in q) / 4 for i in range(3))
        # Walls face the room's centre; block faces face away from the block's centre.
        target = sub(CENTRE, centre) if block_centre is None else sub(centre, block_centre)
        flip = sum(a * b for a, b in zip(n, target)) < 0
        if flip:
            n = tuple(-x for x in n)
        base = len(positions)
        positions.extend(q)
        normals.extend([n] * 4)
        tri = [(0, 1, 2), (0, 2, 3)]
        for t in tri:
            # Counter-clockwise seen from the side the normal points to.
            indices.extend([base + t[0], base + t[2], base + t[1]] if flip else [base + i for i in t])
    return positions, normals, indices


def rotation_from_minus_z(direction):
    """The glTF quaternion (x, y, z, w) turning -z (where glTF lights point) to `direction`."""
    d = normalize(direction)
    axis = cross((0.0, 0.0, -1.0), d)
    s = math.sqrt(sum(a * a for a in axis))
    angle = math.atan2(s, -d[2])
    k = math.sin(0.5 * angle) / s
    return [axis[0] * k, axis[1] * k, axis[2] * k, math.cos(0.5 * angle)]


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    blob = bytearray()
    buffer_views, accessors, meshes, nodes = [], [], [], []
    material_names = list(MATERIALS)

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        buffer_views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(buffer_views) - 1

    for name, (material, quads) in QUADS.items():
        positions, normals, indices = mesh_arrays(name, quads)
        pos_view = add_view(b"".join(struct.pack("<3f", *p) for p in positions), 34962)
        nrm_view = add_view(b"".join(struct.pack("<3f", *n) for n in normals), 34962)
        idx_view = add_view(struct.pack("<%dH" % len(indices), *indices), 34963)
        lo = [min(p[i] for p in positions) for i in range(3)]
        hi = [max(p[i] for p in positions) for i in range(3)]
        accessors.append({"bufferView": pos_view, "componentType": 5126, "count": len(positions),
                          "type": "VEC3", "min": lo, "max": hi})
        accessors.append({"bufferView": nrm_view, "componentType": 5126, "count": len(normals), "type": "VEC3"})
        accessors.append({"bufferView": idx_view, "componentType": 5123, "count": len(indices), "type": "SCALAR"})
        a = len(accessors)
        meshes.append({"name": name, "primitives": [{
            "attributes": {"POSITION": a - 3, "NORMAL": a - 2}, "indices": a - 1,
            "material": material_names.index(material)}]})
        nodes.append({"name": name, "mesh": len(meshes) - 1})

    materials = []
    for name, m in MATERIALS.items():
        mat = {"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": m["baseColorFactor"], "metallicFactor": 0.0, "roughnessFactor": 0.9}}
        if "emissive" in m:
            mat["emissiveFactor"] = m["emissive"]
            mat["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": m["strength"]}}
        materials.append(mat)

    yfov = 2.0 * math.atan(12.5 / 35.0)
    nodes.append({"name": "camera", "camera": 0, "translation": [0.278, 0.273, -0.8],
                  "rotation": [0.0, 1.0, 0.0, 0.0]})
    # A point light below the ceiling light, and a spot from the front left corner.
    nodes.append({"name": "ceiling_light", "translation": [0.278, 0.45, 0.2795],
                  "extensions": {"KHR_lights_punctual": {"light": 0}}})
    nodes.append({"name": "key_spot", "translation": list(SPOT_POSITION),
                  "rotation": rotation_from_minus_z(SPOT_DIRECTION),
                  "extensions": {"KHR_lights_punctual": {"light": 1}}})

    gltf = {
        "asset": {"version": "2.0", "generator": "dhdr testdata/make_cornell_box.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "ceiling_light", "type": "point", "color": [1.0, 0.85, 0.6], "intensity": 0.35, "range": 2.0},
            {"name": "key_spot", "type": "spot", "color": [1.0, 0.95, 0.9], "intensity": 0.25, "range": 1.6,
             "spot": {"innerConeAngle": 0.35, "outerConeAngle": 0.55}}]}},
        "scene": 0,
        "scenes": [{"name": "cornell_box", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": [{"name": "camera", "type": "perspective",
                     "perspective": {"yfov": yfov, "aspectRatio": 1.0, "znear": 0.01, "zfar": 100.0}}],
        "accessors": accessors,
        "bufferViews": buffer_views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
    }
    with open(os.path.join(here, "cornell_box.gltf"), "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")

    lights = {"lights": [
        {"name": "ceiling_light", "type": "point", "position": [0.278, 0.45, 0.2795],
         "color": [1.0, 0.85, 0.6], "intensity": 0.35, "range": 2.0},
        {"name": "key_spot", "type": "spot", "position": list(SPOT_POSITION), "direction": list(SPOT_DIRECTION),
         "color": [1.0, 0.95, 0.9], "intensity": 0.25, "range": 1.6,
         "innerConeAngle": 0.35, "outerConeAngle": 0.55},
        {"name": "fill", "type": "ambient", "color": [1.0, 1.0, 1.0], "intensity": 0.04},
    ]}
    with open(os.path.join(here, "cornell_box.lights.json"), "w") as f:
        json.dump(lights, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    main()
