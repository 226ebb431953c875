#!/usr/bin/env python3
"""Writes testdata/cornell_animated.gltf: the Cornell box (cornell_box.gltf) with a 2-second
animation "shot" (48 frames at 24 fps) for docs/animation.md and the animation benchmark: the
tall block slides left (LINEAR), the short block rises and falls (CUBICSPLINE, its tangents
zero at the ends), and the camera pans 4 degrees to the right (LINEAR rotation, slerp).
"""
import base64
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


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


def main():
    with open(os.path.join(HERE, "cornell_box.gltf")) as f:
        doc = json.load(f)
    nodes = {n["name"]: i for i, n in enumerate(doc["nodes"])}
    doc["animations"] = [{"name": "shot", "samplers": [], "channels": []}]
    anim = doc["animations"][0]

    def accessor(values, kind):
        data = struct.pack("<%df" % len(values), *values)
        doc["buffers"].append({"byteLength": len(data),
                               "uri": "data:application/octet-stream;base64," +
                                      base64.b64encode(data).decode()})
        doc["bufferViews"].append({"buffer": len(doc["buffers"]) - 1, "byteLength": len(data)})
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[kind]
        entry = {"bufferView": len(doc["bufferViews"]) - 1, "componentType": 5126,
                 "count": len(values) // width, "type": kind}
        if kind == "SCALAR":
            entry["min"], entry["max"] = [min(values)], [max(values)]
        doc["accessors"].append(entry)
        return len(doc["accessors"]) - 1

    def channel(node, path, times, values, kind, interpolation="LINEAR"):
        anim["samplers"].append({"input": accessor(times, "SCALAR"),
                                 "output": accessor(values, kind),
                                 "interpolation": interpolation})
        anim["channels"].append({"sampler": len(anim["samplers"]) - 1,
                                 "target": {"node": nodes[node], "path": path}})

    channel("tall_block", "translation", [0.0, 2.0], [0, 0, 0, -0.12, 0, 0], "VEC3")
    # In-tangent, value, out-tangent per key: up 6 cm and back, at rest at the ends.
    zero = [0.0, 0.0, 0.0]
    channel("short_block", "translation", [0.0, 1.0, 2.0],
            zero + zero + zero + zero + [0, 0.06, 0] + zero + zero + zero + zero, "VEC3",
            "CUBICSPLINE")
    base = doc["nodes"][nodes["camera"]]["rotation"]
    channel("camera", "rotation", [0.0, 2.0], base + quat_mul(yaw(-4.0), base), "VEC4")
    with open(os.path.join(HERE, "cornell_animated.gltf"), "w") as f:
        json.dump(doc, f, indent=1)


if __name__ == "__main__":
    main()
