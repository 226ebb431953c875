#!/usr/bin/env python3
"""Writes testdata/shot.gltf, the example shot that docs/examples/shot.farm.json renders on
the farm (docs/animation.md, "A shot on the farm"): the Cornell box for one second (24 frames
at 24 fps, animation "shot") in which

- the tall block turns 90 degrees about its own vertical axis (a pivot node above it, so the
  turn is exact between keys) and the short block hops 6 cm (CUBICSPLINE, as in
  cornell_animated.gltf);
- a skinned arm (one box mesh, two joints: shoulder on the floor, elbow) leans and bends at
  the elbow; the vertices near the elbow are weighted between the two joints, so the mesh
  bends rather than breaks;
- the camera dollies in from outside the box and pans a little to the left;
- a third light, a bright spot near the ceiling at the front, swings from pointing out of the
  box (lighting nothing in view) down onto the floor, towards the back, between 0.2 s and
  0.6 s: the frame gets brighter, and eye adaptation has something to follow. dhdr-gbuffer
  --lights-out writes it where it points at each frame.

Python 3 standard library only; the helpers come from make_cornell_animated.py.
"""
import json
import math
import os

from make_cornell_animated import (HERE, UNSIGNED_BYTE, UNSIGNED_SHORT, GltfWriter,
                                   load_cornell_box, quat_mul, yaw)

FPS = 24
DURATION = 1.0

# The arm: a square section ARM_HALF * 2 wide; the shoulder on the floor at ARM_BASE, the
# elbow UPPER above it, the forearm FOREARM long.
ARM_BASE = (0.39, 0.0, 0.12)
ARM_HALF = 0.022
UPPER, FOREARM = 0.16, 0.12
# Rings of vertices along the arm (heights above the shoulder) and the band around the elbow
# where the weights go from the shoulder to the elbow.
RINGS = [0.0, 0.04, 0.08, 0.12, 0.14, 0.15, 0.16, 0.17, 0.18, 0.20, 0.24, UPPER + FOREARM]
BLEND = (0.13, 0.19)

# The tall block's vertical axis (the centre of its footprint in cornell_box.gltf, metres).
TALL_CENTRE = (0.3685, 0.0, 0.3515)

# The keys, (seconds, degrees), LINEAR; tests/farm/test_shot.py poses the scene from these.
TALL_TURN = [(0.0, 0.0), (0.5, -45.0), (1.0, -90.0)]  # about +y
SHOULDER_ROLL = [(0.0, 0.0), (0.5, 15.0), (1.0, 5.0)]  # about +z
ELBOW_ROLL = [(0.0, 0.0), (0.5, -110.0), (1.0, -50.0)]  # about +z
SWEEP_PITCH = [(0.2, 0.0), (0.6, -125.0)]  # about +x
HOP = 0.06  # the short block's rise at 0.5 s, metres (CUBICSPLINE, tangents 0)


def roll(degrees):
    """A rotation about +z as a quaternion (x, y, z, w): negative angles tip +y towards +x."""
    h = math.radians(degrees) / 2
    return [0.0, 0.0, math.sin(h), math.cos(h)]


def pitch(degrees):
    """A rotation about +x as a quaternion (x, y, z, w)."""
    h = math.radians(degrees) / 2
    return [math.sin(h), 0.0, 0.0, math.cos(h)]


def elbow_weight(height):
    """The elbow joint's weight at a height along the arm; the shoulder has the rest."""
    lo, hi = BLEND
    return min(1.0, max(0.0, (height - lo) / (hi - lo)))


def arm_mesh():
    """Positions, normals, joints, weights and indices of the arm in its bind pose (straight
    up, in world space: the skin's inverse bind matrices undo the joints' rest transforms)."""
    positions, normals, joints, weights, indices = [], [], [], [], []
    bx, _, bz = ARM_BASE
    h = ARM_HALF
    # Each side of the box: its outward normal and its two corners (x, z offsets), counter-
    # clockwise seen from outside.
    sides = [((1, 0, 0), (h, -h), (h, h)), ((0, 0, 1), (h, h), (-h, h)),
             ((-1, 0, 0), (-h, h), (-h, -h)), ((0, 0, -1), (-h, -h), (h, -h))]

    def vertex(p, n, height):
        positions.extend(p)
        normals.extend(n)
        w = elbow_weight(height)
        joints.extend([0, 1, 0, 0])
        weights.extend([1.0 - w, w, 0.0, 0.0])
        return len(positions) // 3 - 1

    for normal, a, b in sides:
        ring = []
        for y in RINGS:
            ring.append((vertex((bx + a[0], y, bz + a[1]), normal, y),
                         vertex((bx + b[0], y, bz + b[1]), normal, y)))
        for (a0, b0), (a1, b1) in zip(ring, ring[1:]):
            indices += [a0, b1, b0, a0, a1, b1]
    top = RINGS[-1]
    cap = [vertex((bx + dx, top, bz + dz), (0, 1, 0), top)
           for dx, dz in ((h, -h), (h, h), (-h, h), (-h, -h))]
    indices += [cap[0], cap[2], cap[1], cap[0], cap[3], cap[2]]
    return positions, normals, joints, weights, indices


def translation(x, y, z):
    """A column-major MAT4 (glTF's order) that translates by (x, y, z)."""
    return [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, y, z, 1]


def add_arm(doc, gltf):
    positions, normals, joints, weights, indices = arm_mesh()
    doc["materials"].append({"name": "arm", "pbrMetallicRoughness": {
        "baseColorFactor": [0.12, 0.28, 0.75, 1.0], "metallicFactor": 0.0,
        "roughnessFactor": 0.5}})
    doc["meshes"].append({"name": "arm", "primitives": [{
        "attributes": {
            "POSITION": gltf.accessor(positions, "VEC3", bounds=True),
            "NORMAL": gltf.accessor(normals, "VEC3"),
            "JOINTS_0": gltf.accessor(joints, "VEC4", UNSIGNED_BYTE),
            "WEIGHTS_0": gltf.accessor(weights, "VEC4")},
        "indices": gltf.accessor(indices, "SCALAR", UNSIGNED_SHORT),
        "material": len(doc["materials"]) - 1}]})
    nodes = doc["nodes"]
    shoulder, elbow, arm = len(nodes), len(nodes) + 1, len(nodes) + 2
    nodes.append({"name": "shoulder", "translation": list(ARM_BASE), "children": [elbow]})
    nodes.append({"name": "elbow", "translation": [0.0, UPPER, 0.0]})
    # The skinned node's own transform does not count (glTF 2.0 §3.7.3): it is left at the
    # root without one.
    nodes.append({"name": "arm", "mesh": len(doc["meshes"]) - 1, "skin": 0})
    bx, by, bz = ARM_BASE
    doc["skins"] = [{"name": "arm", "joints": [shoulder, elbow], "skeleton": shoulder,
                     "inverseBindMatrices": gltf.accessor(
                         translation(-bx, -by, -bz) + translation(-bx, -by - UPPER, -bz),
                         "MAT4")}]
    doc["scenes"][0]["nodes"] += [shoulder, arm]
    gltf.nodes.update({"shoulder": shoulder, "elbow": elbow, "arm": arm})


def add_pivot(doc, gltf, name, centre):
    """Puts node `name` under a new node at `centre`, moved back by −centre, so that turning
    the new node turns `name` about `centre` exactly (at every time, not only at keys)."""
    nodes = doc["nodes"]
    child = gltf.nodes[name]
    pivot = len(nodes)
    nodes[child]["translation"] = [-c for c in centre]
    nodes.append({"name": name + "_pivot", "translation": list(centre), "children": [child]})
    roots = doc["scenes"][0]["nodes"]
    roots[roots.index(child)] = pivot
    gltf.nodes[name + "_pivot"] = pivot


def main():
    doc = load_cornell_box()
    gltf = GltfWriter(doc)
    # The published camera is square; the shot is 4:3, as the demo renders it.
    doc["cameras"][0]["perspective"]["aspectRatio"] = 4.0 / 3.0
    add_pivot(doc, gltf, "tall_block", TALL_CENTRE)
    add_arm(doc, gltf)
    anim = gltf.animation("shot")
    end = DURATION

    def keys(table, quaternion):
        return [t * end for t, _ in table], sum((quaternion(a) for _, a in table), [])

    gltf.channel(anim, "tall_block_pivot", "rotation", *keys(TALL_TURN, yaw), "VEC4")
    zero = [0.0, 0.0, 0.0]
    # In-tangent, value, out-tangent per key: up 6 cm and back, at rest at the ends.
    gltf.channel(anim, "short_block", "translation", [0.0, end / 2, end],
                 zero * 4 + [0, HOP, 0] + zero * 4, "VEC3", "CUBICSPLINE")

    # The arm leans away from the wall while the elbow bends towards it, then straightens a
    # little (a wave: fast enough to blur).
    gltf.channel(anim, "shoulder", "rotation", *keys(SHOULDER_ROLL, roll), "VEC4")
    gltf.channel(anim, "elbow", "rotation", *keys(ELBOW_ROLL, roll), "VEC4")

    # The sweeping spot: glTF lights shine down their node's -z; turning the node about +x by
    # -125 degrees takes -z (out of the box) through straight down to (0, -0.82, 0.57).
    lights = doc["extensions"]["KHR_lights_punctual"]["lights"]
    lights.append({"name": "sweep", "type": "spot", "color": [1.0, 0.9, 0.75],
                   "intensity": 5.0, "range": 2.0,
                   "spot": {"innerConeAngle": 0.35, "outerConeAngle": 0.6}})
    doc["nodes"].append({"name": "sweep", "translation": [0.278, 0.5, 0.05],
                         "extensions": {"KHR_lights_punctual": {"light": len(lights) - 1}}})
    doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    gltf.nodes["sweep"] = len(doc["nodes"]) - 1
    gltf.channel(anim, "sweep", "rotation", *keys(SWEEP_PITCH, pitch), "VEC4")

    # The camera dollies in from outside the box (its front edge in view) to inside its
    # opening, sinking a little, and pans left towards the arm.
    camera = doc["nodes"][gltf.nodes["camera"]]
    start = camera["translation"]
    gltf.channel(anim, "camera", "translation", [0.0, end],
                 [start[0], start[1], -1.0, start[0], start[1] - 0.02, -0.55], "VEC3")
    base = camera["rotation"]
    gltf.channel(anim, "camera", "rotation", [0.0, end], base + quat_mul(yaw(5.0), base),
                 "VEC4")

    with open(os.path.join(HERE, "shot.gltf"), "w") as f:
        json.dump(doc, f, indent=1)


if __name__ == "__main__":
    main()
