#!/usr/bin/env python3
"""The shadow-terminator check (issue 46): a 12-sided cylinder and an 8 x 6 UV sphere, both
with smooth (vertex) normals, under a grazing sun, rendered by dhdr-gbuffer + dhdr-light with
and without shadows, and by Cycles the same way when Blender is installed.

On a lone convex object every point whose shading normal faces the sun is lit (the smooth
surface the normals describe casts no shadow on itself), so the shadowed frame should equal
the unshadowed one wherever N.L > 0; what a renderer's shadow rays take away there is the
faceted terminator. Reported for each renderer, over the objects' pixels the unshadowed frame
lights (luminance above 1 % of its largest):
  lost      the share of that light the shadowed frame loses,
  patches   the pixels darker than 90 % of their unshadowed value (facet-shaped patches),
  spikes    pixels of the unshadowed frame brighter than each of their four neighbours on the
            same object (one at least) by more than 10 % of its largest luminance (single
            bright pixels);
  jump      the 99th percentile of the luminance step between neighbouring pixels on one
            object, shadowed frame, relative to its largest luminance (a facet's edge is a step).
Writes terminator.png (dhdr shadowed | dhdr unshadowed | Cycles shadowed when run) and
terminator.json into --out.

  python3 bench/terminator.py --tools build/apps --out /tmp/term [--cycles] [--size 480x270]
"""
import argparse
import json
import math
import os
import shutil
import struct
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio

ELEVATION = 8.0  # degrees: the sun's height above the horizon (grazing)
AZIMUTH = 80.0   # degrees: from the left, a little in front; the cylinder's terminator a third into a facet
SUN_LUX = 3.0


def sun_travel():
    e, a = math.radians(ELEVATION), math.radians(AZIMUTH)
    towards = (-math.cos(e) * math.sin(a), math.sin(e), math.cos(e) * math.cos(a))
    return [-c for c in towards]


def cylinder(cx, cz, radius, height, sides):
    """Side wall only, each vertex normal the circle's radial direction (smooth)."""
    positions, normals, indices = [], [], []
    for j in range(sides + 1):
        phi = 2 * math.pi * j / sides
        n = (math.cos(phi), 0.0, -math.sin(phi))
        for y in (0.0, height):
            positions.append((cx + radius * n[0], y, cz + radius * n[2]))
            normals.append(n)
    for j in range(sides):
        a, b = 2 * j, 2 * j + 2
        indices += [a, b, a + 1, b, b + 1, a + 1]
    return positions, normals, indices


def uv_sphere(cx, cy, cz, r, rings, segments):
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
            if i > 0:
                indices += [a, a + 1, b]
            if i < rings - 1:
                indices += [a + 1, b + 1, b]
    return positions, normals, indices


def write_gltf(path, objects):
    blob = bytearray()
    views, accessors, meshes, nodes = [], [], [], []

    def view(data, target):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(views) - 1

    for name, (positions, normals, indices) in objects:
        pv = view(b"".join(struct.pack("<3f", *p) for p in positions), 34962)
        nv = view(b"".join(struct.pack("<3f", *n) for n in normals), 34962)
        iv = view(struct.pack("<%dI" % len(indices), *indices), 34963)
        lo = [min(p[i] for p in positions) for i in range(3)]
        hi = [max(p[i] for p in positions) for i in range(3)]
        k = len(accessors)
        accessors += [
            {"bufferView": pv, "componentType": 5126, "count": len(positions), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": nv, "componentType": 5126, "count": len(normals), "type": "VEC3"},
            {"bufferView": iv, "componentType": 5125, "count": len(indices), "type": "SCALAR"}]
        meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": k, "NORMAL": k + 1},
                                                      "indices": k + 2, "material": 0}]})
        nodes.append({"name": name, "mesh": len(meshes) - 1})
    gltf = {
        "asset": {"version": "2.0", "generator": "bench/terminator.py"},
        "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes, "meshes": meshes,
        "materials": [{"name": "white", "pbrMetallicRoughness": {
            "baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "accessors": accessors, "bufferViews": views,
        "buffers": [{"byteLength": len(blob), "uri": os.path.basename(path)[:-5] + ".bin"}],
    }
    with open(path[:-5] + ".bin", "wb") as f:
        f.write(blob)
    with open(path, "w") as f:
        json.dump(gltf, f, indent=1)


OBJECTS = ["cylinder12", "sphere8x6"]
CAMERA = "0,0.55,3.2,0,0.35,0"
FOV = 30.0


def run(cmd):
    subprocess.run(cmd, check=True)


def render_dhdr(tools, scene, out, size, angle):
    lights = os.path.join(out, "sun.lights.json")
    with open(lights, "w") as f:
        json.dump({"lights": [{"type": "directional", "direction": sun_travel(), "intensity": SUN_LUX,
                               "angle": angle}]}, f)
    gbuf = os.path.join(out, "terminator.gbuf.exr")
    run([os.path.join(tools, "dhdr-gbuffer"), scene, "-o", gbuf, "--size", size, "--lookat", CAMERA,
         "--fov", str(FOV), "-q"])
    frames = {}
    for name, extra in (("shadowed", []), ("unshadowed", ["--no-shadows"])):
        path = os.path.join(out, "dhdr_%s.exr" % name)
        run([os.path.join(tools, "dhdr-light"), gbuf, "--scene", scene, "--lights", lights, "-o", path,
             "--type", "float", "-q"] + extra)
        frames[name] = read(path)
    ids = oiio.ImageBuf(gbuf)
    names = ids.spec().channelnames
    obj = ids.get_pixels(oiio.UINT32)[:, :, names.index("id.object")].astype(np.int64)
    return frames, obj


CYCLES_SCRIPT = r'''
import bpy, math, sys
import numpy
numpy.bool = bool  # Blender 3.4's glTF importer uses the alias NumPy 1.24 removed
argv = sys.argv[sys.argv.index("--") + 1:]
scene_path, out, w, h, travel, angle, lux, shadows = argv[0], argv[1], int(argv[2]), int(argv[3]), \
    [float(v) for v in argv[4].split(",")], float(argv[5]), float(argv[6]), argv[7] == "1"
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=scene_path)
sc = bpy.context.scene
sc.render.engine = "CYCLES"
sc.cycles.samples = 64
sc.cycles.use_denoising = False
sc.cycles.max_bounces = 0
sc.render.resolution_x, sc.render.resolution_y = w, h
sc.render.image_settings.file_format = "OPEN_EXR"
sc.render.image_settings.color_depth = "32"
sc.view_settings.view_transform = "Standard"
world = bpy.data.worlds.new("w"); sc.world = world; world.use_nodes = True
world.node_tree.nodes["Background"].inputs[1].default_value = 0.0
for ob in sc.objects:
    if ob.type == "MESH":
        ob.visible_shadow = shadows
        for poly in ob.data.polygons:
            poly.use_smooth = True
        mat = ob.active_material
        mat.use_nodes = True
        nt = mat.node_tree
        nt.nodes.clear()
        d = nt.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs[0].default_value = (0.8, 0.8, 0.8, 1.0)
        o = nt.nodes.new("ShaderNodeOutputMaterial")
        nt.links.new(d.outputs[0], o.inputs[0])
sun = bpy.data.lights.new("sun", "SUN")
sun.energy = lux  # ratios only are compared: the units cancel
sun.angle = math.radians(angle)
so = bpy.data.objects.new("sun", sun); sc.collection.objects.link(so)
from mathutils import Vector
def blender(v):  # glTF's y-up to Blender's z-up, as the importer turns the meshes
    return Vector((v[0], -v[2], v[1]))
so.rotation_euler = blender(travel).to_track_quat("-Z", "Y").to_euler()
eye = blender((%(eye)s)); target = blender((%(target)s))
cam = bpy.data.cameras.new("cam"); cam.sensor_fit = "VERTICAL"; cam.angle_y = math.radians(%(fov)s)
co = bpy.data.objects.new("cam", cam); sc.collection.objects.link(co); sc.camera = co
co.location = eye
co.rotation_euler = (target - eye).to_track_quat("-Z", "Y").to_euler()
sc.render.filepath = out
bpy.ops.render.render(write_still=True)
'''


def render_cycles(blender, scene, out, size, angle):
    w, h = size.split("x")
    eye, target = CAMERA.split(",")[:3], CAMERA.split(",")[3:]
    script = os.path.join(out, "cycles_terminator.py")
    with open(script, "w") as f:
        f.write(CYCLES_SCRIPT % {"eye": ",".join(eye), "target": ",".join(target), "fov": FOV})
    frames = {}
    for name, flag in (("shadowed", "1"), ("unshadowed", "0")):
        path = os.path.join(out, "cycles_%s.exr" % name)
        run([blender, "-b", "--factory-startup", "--python", script, "--", os.path.abspath(scene), path, w, h,
             ",".join("%.9g" % c for c in sun_travel()), str(angle), str(SUN_LUX), flag])
        frames[name] = read(path)
    return frames


def read(path):
    buf = oiio.ImageBuf(path)
    return buf.get_pixels(oiio.FLOAT)[:, :, :3]


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def measure(frames, obj):
    sh, un = luminance(frames["shadowed"]), luminance(frames["unshadowed"])
    lit = (obj > 0) & (un > 0.01 * un.max())
    lost = float((un[lit] - sh[lit]).clip(min=0).sum() / un[lit].sum())
    patches = int(((sh < 0.9 * un) & lit).sum())
    steps = []
    for axis in (0, 1):
        same = (np.diff(obj, axis=axis) == 0) & (np.delete(obj, 0, axis=axis) > 0)
        steps.append(np.abs(np.diff(sh, axis=axis))[same])
    jump = float(np.percentile(np.concatenate(steps), 99) / sh.max())
    # Against the neighbours on the same object only (a silhouette pixel has background ones).
    c = un[1:-1, 1:-1]
    brighter = obj[1:-1, 1:-1] > 0
    neighbours = np.zeros(c.shape, dtype=int)
    for dy, dx in ((-1, 0), (1, 0), (0, -1), (0, 1)):
        n = un[1 + dy:un.shape[0] - 1 + dy, 1 + dx:un.shape[1] - 1 + dx]
        same = obj[1 + dy:obj.shape[0] - 1 + dy, 1 + dx:obj.shape[1] - 1 + dx] == obj[1:-1, 1:-1]
        neighbours += same
        brighter &= ~same | (c > n + 0.1 * un.max())
    spikes = int((brighter & (neighbours > 0)).sum())
    per_object = {}
    # OpenImageIO hands the uint ids back converted; their order is the objects' order.
    for rank, k in enumerate(sorted(set(np.unique(obj)) - {0})):
        m = lit & (obj == k)
        per_object[OBJECTS[rank]] = {"lost": float((un[m] - sh[m]).clip(min=0).sum() / un[m].sum()),
                              "patches": int(((sh < 0.9 * un) & m).sum()), "pixels": int(m.sum())}
    return {"lost": lost, "patches": patches, "lit_pixels": int(lit.sum()), "spikes": spikes, "jump_p99": jump,
            "objects": per_object}


def to_png(images, path):
    top = max(float(np.percentile(luminance(i), 99.5)) for i in images)
    row = np.concatenate([np.clip(i / top, 0, 1) ** (1 / 2.2) for i in images], axis=1)
    out = oiio.ImageBuf(oiio.ImageSpec(row.shape[1], row.shape[0], 3, oiio.UINT8))
    out.set_pixels(oiio.ROI(), (row * 255 + 0.5).astype(np.uint8))
    out.write(path)


def labelled(rgb, text):
    buf = oiio.ImageBuf(oiio.ImageSpec(rgb.shape[1], rgb.shape[0], 3, oiio.FLOAT))
    buf.set_pixels(oiio.ROI(), np.ascontiguousarray(rgb.astype(np.float32)))
    if not oiio.ImageBufAlgo.render_text(buf, 8, 22, text, 18, "DejaVuSans", (1.0, 0.8, 0.2)):
        print("no label:", buf.geterror(), file=sys.stderr)
    return buf.get_pixels(oiio.FLOAT)


def docs_picture(before, after, path):
    """docs/images/terminator.png: before | after (shadowed frames) over before unshadowed |
    Cycles, cropped to the objects."""
    crop = (slice(40, 220), slice(90, 430))
    frames = {name: read(os.path.join(d, f))[crop] for name, d, f in (
        ("before", before, "dhdr_shadowed.exr"), ("after", after, "dhdr_shadowed.exr"),
        ("unshadowed", before, "dhdr_unshadowed.exr"), ("cycles", after, "cycles_shadowed.exr"))}
    top = max(float(np.percentile(luminance(f), 99.5)) for f in frames.values())
    def tone(f):
        return np.clip(f / top, 0, 1) ** (1 / 2.2)
    rows = [np.concatenate([labelled(tone(frames["before"]), "before"),
                            labelled(tone(frames["after"]), "after")], axis=1),
            np.concatenate([labelled(tone(frames["unshadowed"]), "before, no shadows"),
                            labelled(tone(frames["cycles"]), "Cycles")], axis=1)]
    grid = np.concatenate(rows, axis=0)
    out = oiio.ImageBuf(oiio.ImageSpec(grid.shape[1], grid.shape[0], 3, oiio.UINT8))
    out.set_pixels(oiio.ROI(), (np.clip(grid, 0, 1) * 255 + 0.5).astype(np.uint8))
    out.write(path)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--tools", default="build/apps")
    p.add_argument("--out", default="/tmp/terminator")
    p.add_argument("--size", default="480x270")
    p.add_argument("--angle", type=float, default=0.0, help="the sun's angular diameter, degrees")
    p.add_argument("--cycles", action="store_true", help="also render with Blender's Cycles")
    p.add_argument("--docs-picture", nargs=2, metavar=("BEFORE_DIR", "PNG"),
                   help="compose the docs picture from an earlier run's --out (the tools before the "
                        "fix) and this run's (with --cycles), then stop")
    a = p.parse_args()
    if a.docs_picture:
        docs_picture(a.docs_picture[0], a.out, a.docs_picture[1])
        return
    os.makedirs(a.out, exist_ok=True)
    scene = os.path.join(a.out, "terminator.gltf")
    # The sun comes from the left: the cylinder stands behind, so that its shadow falls away
    # from the sphere (each object lit alone).
    write_gltf(scene, [("cylinder12", cylinder(-0.6, -0.4, 0.35, 0.8, 12)),
                       ("sphere8x6", uv_sphere(0.6, 0.4, 0.4, 0.4, 6, 8))])
    frames, obj = render_dhdr(a.tools, scene, a.out, a.size, a.angle)
    report = {"sun": {"travel": sun_travel(), "elevation": ELEVATION, "angle": a.angle},
              "dhdr": measure(frames, obj)}
    images = [frames["shadowed"], frames["unshadowed"]]
    if a.cycles:
        blender = shutil.which("blender")
        if not blender:
            sys.exit("--cycles: no blender on PATH")
        cycles = render_cycles(blender, scene, a.out, a.size, a.angle)
        report["cycles"] = measure(cycles, obj)
        images.append(cycles["shadowed"])
    to_png(images, os.path.join(a.out, "terminator.png"))
    with open(os.path.join(a.out, "terminator.json"), "w") as f:
        json.dump(report, f, indent=1)
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
