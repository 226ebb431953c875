"""Relights Blender's render passes under new lights and composites the result over a plate,
all in memory: the passes read as dhdr-light --channels blender reads them, the lights moved
in Python, the composite "over" the photograph, tone-mapped once at the end (docs/python.md).

    python3 blender_composite.py PASSES.exr LIGHTS.json PLATE.exr OUT.png
"""
import sys

import numpy as np

import dhdr


def main(passes_path, lights_path, plate_path, out_path):
    # Cycles' Depth, Position, Normal (Z up) and BaseColor/Roughness/Metallic AOVs; the camera
    # from the file's worldToCamera/worldToNDC.
    gbuffer = dhdr.import_gbuffer(dhdr.read_channels(passes_path), "blender")
    lights = dhdr.read_lights(lights_path)
    for light in lights:  # a warmer key
        if light["type"] != "ambient":
            light["color"] = [1.0, 0.8, 0.6]
    # Blender's exporter writes photometric intensities: radiometric=True divides by 683.
    lit = dhdr.light(gbuffer, lights, radiometric=True)
    plate = dhdr.read(plate_path, keep_others=False)
    # "over" with numpy: the objects (premultiplied RGB, A) onto the plate.
    rgba, bg = lit.pixels, plate.pixels
    comp = rgba[..., :3] + bg[..., :3] * (1.0 - rgba[..., 3:4])
    frame = dhdr.Image(np.concatenate([comp, np.ones_like(rgba[..., 3:4])], axis=2),
                       ["R", "G", "B", "A"])
    dhdr.write(out_path, dhdr.tonemap_frame(frame, bits=8))
    return lit, frame


if __name__ == "__main__":
    main(*sys.argv[1:5])
