#!/usr/bin/env python3
"""Writes cornell_transmission.gltf into the folder given (default: this one): cornell_glass.gltf
(make_cornell_glass.py) with its pane made of glass as KHR_materials_transmission writes it
(opaque, transmissionFactor 1, a cyan tint, roughness 0.05) instead of a BLEND alpha of 0.4, for
docs/scenes.md's transmission picture.
"""
import json
import os
import sys


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else here
    with open(os.path.join(here, "cornell_glass.gltf")) as f:
        gltf = json.load(f)
    for m in gltf["materials"]:
        if m["name"] == "glass":
            m.pop("alphaMode", None)
            m["pbrMetallicRoughness"] = {"baseColorFactor": [0.55, 0.85, 1.0, 1.0],
                                         "metallicFactor": 0.0, "roughnessFactor": 0.05}
            m["extensions"] = {"KHR_materials_transmission": {"transmissionFactor": 1.0}}
    gltf.setdefault("extensionsUsed", []).append("KHR_materials_transmission")
    # The card's texture stays where make_cornell_glass.py wrote it.
    for image in gltf.get("images", []):
        if "uri" in image and not image["uri"].startswith("data:"):
            image["uri"] = os.path.relpath(os.path.join(here, image["uri"]), out)
    with open(os.path.join(out, "cornell_transmission.gltf"), "w") as f:
        json.dump(gltf, f)


if __name__ == "__main__":
    main()
