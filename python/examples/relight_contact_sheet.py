"""Relights one G-buffer under ten positions of a point light and saves a contact sheet (a
5 x 2 grid of the ten frames), without writing an EXR in between (docs/python.md).

    python3 relight_contact_sheet.py FRAME.gbuf.exr LIGHTS.json SHEET.png
"""
import math
import sys

import numpy as np

import dhdr


def main(gbuffer_path, lights_path, out_path):
    gbuffer = dhdr.read_gbuffer(gbuffer_path)
    lights = dhdr.read_lights(lights_path)  # the file's lights as dicts
    bulb = next(l for l in lights if l["type"] == "point")
    centre = bulb["position"]
    frames = []
    for i in range(10):
        # The bulb on a circle of 15 cm around its place in the file.
        angle = 2.0 * math.pi * i / 10.0
        bulb["position"] = [centre[0] + 0.15 * math.cos(angle), centre[1],
                            centre[2] + 0.15 * math.sin(angle)]
        frames.append(dhdr.light(gbuffer, lights))
    # One exposure for the whole sheet (the first frame's metering), so that the frames
    # compare: tone-mapping each on its own would even their brightness out.
    stats = dhdr.meter(frames[0])
    shown = [dhdr.tonemap_frame(f, stats=stats, bits=8).astype(np.uint8) for f in frames]
    rows = [np.concatenate(shown[r * 5:(r + 1) * 5], axis=1) for r in range(2)]
    dhdr.write(out_path, np.ascontiguousarray(np.concatenate(rows, axis=0)))


if __name__ == "__main__":
    main(*sys.argv[1:4])
