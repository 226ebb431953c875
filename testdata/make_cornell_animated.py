#!/usr/bin/env python3
"""Writes testdata/cornell_animated.gltf: the Cornell box (cornell_box.gltf) with a 2-second
animation "shot" (48 frames at 24 fps) for docs/animation.md and the animation benchmark: the
tall block slides left (LINEAR), the short block rises and falls (CUBICSPLINE, its tangents
zero at the ends), and the camera pans 4 degrees to the right (LINEAR rotation, slerp).

The helpers (GltfWriter, quat_mul, yaw) are imported by make_shot.py, which builds the farm's
example shot on the same box.
"""
import base64
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

FLOAT, UNSIGNED_BYTE, UNSIGNED_SHORT = 5126, 5121, 5123
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def quat_mul(a, b):
    """Hamilton product of quaternions (x, y, z, w)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz]


def yaw(degrees):
    h = math.radians(degrees) / 2
    return [0.0, math.sin(h), 0.0, math.cos(h)]


def load_cornell_box():
    with open(os.path.join(HERE, "cornell_box.gltf")) as f:
        return json.load(f)


class GltfWriter:
    """Appends accessors and animation channels to a glTF document held as JSON. Each accessor
    gets its own buffer, a data: URI, so that the file stays one self-contained text file."""

    def __init__(self, doc):
        self.doc = doc
        self.nodes = {n["name"]: i for i, n in enumerate(doc["nodes"])}

    def accessor(self, values, kind, component=FLOAT, bounds=False):
        """`values` flat; SCALAR accessors get min and max (glTF requires them on animation
        inputs), and so does any accessor with `bounds` (POSITION requires them)."""
        code = {FLOAT: "f", UNSIGNED_BYTE: "B", UNSIGNED_SHORT: "H"}[component]
        data = struct.pack("<%d%s" % (len(values), code), *values)
        data += b"\0" * (-len(data) % 4)  # buffer views of floats start on 4 bytes
        doc = self.doc
        doc["buffers"].append({"byteLength": len(data),
                               "uri": "data:application/octet-stream;base64," +
                                      base64.b64encode(data).decode()})
        doc["bufferViews"].append({"buffer": len(doc["buffers"]) - 1, "byteLength": len(data)})
        width = WIDTH[kind]
        entry = {"bufferView": len(doc["bufferViews"]) - 1, "componentType": component,
                 "count": len(values) // width, "type": kind}
        if kind == "SCALAR" or bounds:
            entry["min"] = [min(values[c::width]) for c in range(width)]
            entry["max"] = [max(values[c::width]) for c in range(width)]
        doc["accessors"].append(entry)
        return len(doc["accessors"]) - 1

    def animation(self, name):
        self.doc.setdefault("animations", []).append(
            {"name": name, "samplers": [], "channels": []})
        return self.doc["animations"][-1]

    def channel(self, anim, node, path, times, values, kind, interpolation="LINEAR"):
        anim["samplers"].append({"input": self.accessor(times, "SCALAR"),
                                 "output": self.accessor(values, kind),
                                 "interpolation": interpolation})
        anim["channels"].append({"sampler": len(anim["samplers"]) - 1,
                                 "target": {"node": self.nodes[node], "path": path}})


def main():
    doc = load_cornell_box()
    gltf = GltfWriter(doc)
    anim = gltf.animation("shot")
    gltf.channel(anim, "tall_block", "translation", [0.0, 2.0], [0, 0, 0, -0.12, 0, 0], "VEC3")
    # In-tangent, value, out-tangent per key: up 6 cm and back, at rest at the ends.
    zero = [0.0, 0.0, 0.0]
    gltf.channel(anim, "short_block", "translation", [0.0, 1.0, 2.0],
                 zero + zero + zero + zero + [0, 0.06, 0] + zero + zero + zero + zero, "VEC3",
                 "CUBICSPLINE")
    base = doc["nodes"][gltf.nodes["camera"]]["rotation"]
    gltf.channel(anim, "camera", "rotation", [0.0, 2.0], base + quat_mul(yaw(-4.0), base),
                 "VEC4")
    with open(os.path.join(HERE, "cornell_animated.gltf"), "w") as f:
        json.dump(doc, f, indent=1)


if __name__ == "__main__":
    main()
