#!/usr/bin/env python3
"""KHR_materials_pbrSpecularGlossiness's specularGlossinessTexture in dhdr-gbuffer against
Blender's own glTF importer (issue 44): a square whose diffuse and specular-glossiness textures
(4 x 1 texels, NEAREST) vary along u, rendered head-on by dhdr-gbuffer (64 x 64) and baked by
Blender head-on too (bake.py). Per texel it compares dhdr's specular.RGB (F0) with what Blender
feeds its Glossy BSDF's colour, dhdr's roughness with the Glossy BSDF's roughness, and dhdr's
albedo / (1 - max F0) with the Diffuse BSDF's colour (Blender adds diffuse and glossy without
dimming the diffuse; dhdr dims it as the extension's README says).

    python3 bench/specgloss_blender/compare.py --bin build/apps [--keep DIR]
"""
import argparse
import base64
import json
import os
import struct
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

DIFFUSE = [[255, 255, 255, 255], [200, 150, 100, 255], [128, 128, 128, 255], [50, 100, 200, 255]]
SG = [[64, 64, 64, 255], [200, 100, 50, 128], [128, 200, 255, 16], [30, 30, 30, 200]]
DF, SF, GF = [0.9, 0.8, 0.7], [0.6, 0.8, 0.9], 0.9


def write_png(path, texels):
    spec = oiio.ImageSpec(len(texels), 1, 4, "uint8")
    spec.attribute("oiio:UnassociatedAlpha", 1)
    out = oiio.ImageOutput.create(path)
    out.open(path, spec)
    out.write_image(np.array([texels], dtype=np.uint8))
    out.close()


def write_scene(folder):
    write_png(os.path.join(folder, "diffuse.png"), DIFFUSE)
    write_png(os.path.join(folder, "sg.png"), SG)
    pos = [-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0]
    nor = [0, 0, 1] * 4
    uv = [0, 1, 1, 1, 1, 0, 0, 0]
    data = (struct.pack("12f", *pos) + struct.pack("12f", *nor) + struct.pack("8f", *uv)
            + struct.pack("6I", 0, 1, 2, 0, 2, 3))
    views = [(0, 48), (48, 48), (96, 32), (128, 24)]
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [-1, -1, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                      {"bufferView": 3, "componentType": 5125, "count": 6, "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                    "indices": 3, "material": 0}]}],
        "materials": [{"name": "sg", "extensions": {"KHR_materials_pbrSpecularGlossiness": {
            "diffuseFactor": DF + [1.0], "specularFactor": SF, "glossinessFactor": GF,
            "diffuseTexture": {"index": 0}, "specularGlossinessTexture": {"index": 1}}}}],
        "images": [{"uri": "diffuse.png"}, {"uri": "sg.png"}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}],
        "nodes": [{"name": "square", "mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "extensionsUsed": ["KHR_materials_pbrSpecularGlossiness"],
    }
    path = os.path.join(folder, "sg.gltf")
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def read(path):
    buf = oiio.ImageBuf(path)
    return buf.get_pixels(oiio.FLOAT), list(buf.spec().channelnames)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", required=True)
    ap.add_argument("--keep")
    args = ap.parse_args()
    folder = args.keep or tempfile.mkdtemp()
    os.makedirs(folder, exist_ok=True)
    gltf = write_scene(folder)
    g_path = os.path.join(folder, "gbuffer.exr")
    subprocess.run([os.path.join(args.bin, "dhdr-gbuffer"), gltf, "--lookat", "0,0,3,0,0,0",
                    "--fov", "60", "--size", "64x64", "-o", g_path], check=True)
    g, names = read(g_path)
    for mode in ("as imported", "channel packed"):
        print(f"Blender's import, {mode}:")
        compare(g, names, folder, gltf, mode == "channel packed")


def compare(g, names, folder, gltf, packed):
    blender = subprocess.run(["blender", "-b", "--python", os.path.join(os.path.dirname(__file__),
                              "bake.py"), "--", gltf, os.path.join(folder, "blender")]
                             + (["packed"] if packed else []),
                             check=True, stdout=subprocess.PIPE, text=True)
    for line in blender.stdout.splitlines():
        if line.startswith("compare:"):
            print(line)
    ch = {n: i for i, n in enumerate(names)}
    baked = {k: read(os.path.join(folder, f"blender_{k}.exr"))[0]
             for k in ("glossy", "roughness", "diffuse")}
    print("texel  quantity        dhdr                        Blender")
    worst = {}
    for i in range(4):
        # dhdr: the pixel of row 32 nearest u = (i + 0.5) / 4; Blender's image is the square.
        xs = [x for x in range(64) if g[32, x, ch["A"]] == 1]
        x = min(xs, key=lambda x: abs((g[32, x, ch["P.X"]] + 1) / 2 - (i + 0.5) / 4))
        bx = int((i + 0.5) / 4 * 64)
        f0 = np.array([g[32, x, ch[f"specular.{c}"]] for c in "RGB"])
        albedo = np.array([g[32, x, ch[f"albedo.{c}"]] for c in "RGB"])
        rough = g[32, x, ch["roughness"]]
        rows = [("F0 / glossy", f0, baked["glossy"][32, bx, :3]),
                ("roughness", np.array([rough]), baked["roughness"][32, bx, :1]),
                ("undimmed diffuse", albedo / (1 - f0.max()), baked["diffuse"][32, bx, :3])]
        for name, mine, theirs in rows:
            worst[name] = max(worst.get(name, 0), float(np.abs(mine - theirs).max()))
            print(f"{i}      {name:16s} {np.round(mine, 4)!s:27s} {np.round(theirs, 4)}")
    for name, d in worst.items():
        print(f"largest difference, {name}: {d:.5f}")


if __name__ == "__main__":
    sys.exit(main())
