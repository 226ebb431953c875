#!/usr/bin/env python3
"""Writes testdata/cornell_gold.gltf: the Cornell box of make_cornell_box.py with its tall
block turned into gold (metallic 1, base colour (1, 0.78, 0.34), roughness 0.25), for the
specular indirect light: the room reflected in a metal (docs/gi.md).
"""
import json
import os


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "cornell_box.gltf")) as f:
        gltf = json.load(f)
    gltf["materials"].append({"name": "gold", "pbrMetallicRoughness": {
        "baseColorFactor": [1.0, 0.78, 0.34, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.25}})
    gold = len(gltf["materials"]) - 1
    for mesh in gltf["meshes"]:
        if mesh["name"] == "tall_block":
            for primitive in mesh["primitives"]:
                primitive["material"] = gold
    with open(os.path.join(here, "cornell_gold.gltf"), "w") as f:
        json.dump(gltf, f, indent=None, separators=(",", ":"))
        f.write("\n")


if __name__ == "__main__":
    main()
