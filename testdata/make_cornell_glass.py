#!/usr/bin/env python3
"""Writes testdata/cornell_glass.gltf (and card_holes.png): the Cornell box of
make_cornell_box.py with a glass pane (alphaMode BLEND, alpha 0.4) standing beside the tall
block and a card with square holes (alphaMode MASK, a checker texture whose dark squares have
alpha 0) behind it, for deep G-buffers (docs/gbuffer.md).
"""
import base64
import json
import os
import struct
import subprocess

import make_cornell_box as cb

# The pane stands on the floor between the blocks, lit from the front by the ceiling light;
# the card hangs behind it, in front of the back wall, so that some pixels see glass, card and
# wall, and the card's shadow with its holes falls on the wall.
PANE = {"name": "glass_pane", "material": "glass",
        "quad": [(0.33, 0.0, 0.32), (0.09, 0.0, 0.32), (0.09, 0.34, 0.32), (0.33, 0.34, 0.32)]}
CARD = {"name": "cut_card", "material": "card",
        "quad": [(0.26, 0.12, 0.46), (0.04, 0.12, 0.46), (0.04, 0.34, 0.46), (0.26, 0.34, 0.46)]}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    subprocess.run(["oiiotool", "--pattern", "checker:width=16:height=16:color1=0.9,0.75,0.3,1:color2=0,0,0,0",
                    "64x64", "4", "-d", "uint8", "-o", os.path.join(here, "card_holes.png")], check=True)
    cb.main()  # writes cornell_box.gltf, which this file extends
    with open(os.path.join(here, "cornell_box.gltf")) as f:
        gltf = json.load(f)
    blob = bytearray(base64.b64decode(gltf["buffers"][0]["uri"].split(",", 1)[1]))

    def add_view(data):
        while len(blob) % 4:
            blob.append(0)
        gltf["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        blob.extend(data)
        return len(gltf["bufferViews"]) - 1

    gltf["materials"].append({"name": "glass", "alphaMode": "BLEND", "pbrMetallicRoughness": {
        "baseColorFactor": [0.55, 0.75, 0.9, 0.4], "metallicFactor": 0.0, "roughnessFactor": 0.1}})
    gltf["materials"].append({"name": "card", "alphaMode": "MASK", "alphaCutoff": 0.5,
                              "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                                                       "baseColorTexture": {"index": 0},
                                                       "metallicFactor": 0.0, "roughnessFactor": 0.8}})
    gltf["images"] = [{"uri": "card_holes.png"}]
    gltf["samplers"] = [{"magFilter": 9728, "minFilter": 9728}]
    gltf["textures"] = [{"source": 0, "sampler": 0}]
    for item in (PANE, CARD):
        q = item["quad"]
        positions = b"".join(struct.pack("<3f", *p) for p in q)
        normals = b"".join(struct.pack("<3f", 0.0, 0.0, -1.0) for _ in q)
        uvs = b"".join(struct.pack("<2f", *uv) for uv in [(0, 1), (1, 1), (1, 0), (0, 0)])
        indices = struct.pack("<6H", 0, 2, 1, 0, 3, 2)
        acc = gltf["accessors"]
        lo = [min(p[i] for p in q) for i in range(3)]
        hi = [max(p[i] for p in q) for i in range(3)]
        acc.append({"bufferView": add_view(positions), "componentType": 5126, "count": 4, "type": "VEC3",
                    "min": lo, "max": hi})
        acc.append({"bufferView": add_view(normals), "componentType": 5126, "count": 4, "type": "VEC3"})
        acc.append({"bufferView": add_view(uvs), "componentType": 5126, "count": 4, "type": "VEC2"})
        acc.append({"bufferView": add_view(indices), "componentType": 5123, "count": 6, "type": "SCALAR"})
        a = len(acc)
        names = [m["name"] for m in gltf["materials"]]
        gltf["meshes"].append({"name": item["name"], "primitives": [{
            "attributes": {"POSITION": a - 4, "NORMAL": a - 3, "TEXCOORD_0": a - 2}, "indices": a - 1,
            "material": names.index(item["material"])}]})
        gltf["nodes"].append({"name": item["name"], "mesh": len(gltf["meshes"]) - 1})
        gltf["scenes"][0]["nodes"].append(len(gltf["nodes"]) - 1)
    gltf["buffers"][0] = {"byteLength": len(blob),
                          "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}
    gltf["asset"]["generator"] = "dhdr testdata/make_cornell_glass.py"
    with open(os.path.join(here, "cornell_glass.gltf"), "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
