#!/usr/bin/env python3
"""Texture filtering in dhdr-gbuffer (--texture-filter): a checkered floor receding to the
horizon (a 256² PNG of 4-texel cells, tiled 40 times over a 200 × 200 floor), its albedo at
1 sample a pixel with each filter against the average of 16 × 16 rays a pixel (the pixel's box):
RMS error over the floor's pixels; shimmer, the RMS difference between two frames whose
cameras turn half a pixel apart once aligned (each frame's neighbouring pixels averaged); trace
time and peak memory. With --picture, the docs' picture of the four.

    /usr/bin/python3 bench/texture_filtering.py --bin build/apps [--size 480x270]
        [--rays 16] [--picture docs/images/texture_filtering.png]
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lights import run  # noqa: E402
from materials import mesh_document  # noqa: E402

FILTERS = ("bilinear", "trilinear", "anisotropic")
EYE = (0.0, 1.0, 0.0)
FOV = 40.0


def floor_scene(path):
    """The floor as a glTF file beside `checker.png`."""
    doc = mesh_document([([-100, 0, -100, 100, 0, -100, 100, 0, 100, -100, 0, 100], [0, 1, 0] * 4,
                          [0, 0, 40, 0, 40, 40, 0, 40], [0, 2, 1, 0, 3, 2])])
    doc["images"] = [{"uri": "checker.png"}]
    doc["textures"] = [{"source": 0}]
    doc["materials"] = [{"name": "checker", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": 0}, "metallicFactor": 0, "roughnessFactor": 1}}]
    with open(path, "w") as f:
        json.dump(doc, f)


def lookat(yaw):
    """--lookat for the camera 1 unit above the floor looking down 8° and turned by `yaw`."""
    pitch = math.radians(-8.0)
    d = (math.sin(yaw) * math.cos(pitch), math.sin(pitch), -math.cos(yaw) * math.cos(pitch))
    return ",".join("%.9f" % v for v in EYE + tuple(EYE[i] + d[i] for i in range(3)))


def albedo(tool, scene, work, size, flt, yaw=0.0, extra=()):
    # A file per render: OpenImageIO's cache would hand back an earlier file of the same name.
    out = os.path.join(work, "g_%s_%dx%d_%g.exr" % (flt, size[0], size[1], yaw))
    wall, rss, err = run([tool, scene, "--lookat", lookat(yaw), "--fov", str(FOV), "--size",
                          "%dx%d" % size, "--texture-filter", flt, "-o", out, "-v"] + list(extra))
    # Only the channels used: this process's own peak memory stays small (see main()).
    inp = oiio.ImageInput.open(out)
    names = inp.spec().channelnames
    r = names.index("albedo.R")
    rgb = inp.read_image(0, 0, r, r + 3, oiio.FLOAT)
    a = inp.read_image(0, 0, names.index("A"), names.index("A") + 1, oiio.FLOAT)[:, :, 0]
    inp.close()
    os.remove(out)
    trace = float(re.search(r"trace ([0-9.]+) ms", err).group(1))
    return rgb, a, trace, wall, rss


def box(img, s):
    h, w = img.shape[0] // s, img.shape[1] // s
    return img.reshape(h, s, w, s, *img.shape[2:]).mean(axis=(1, 3))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", default="480x270")
    ap.add_argument("--picture", help="write the docs' picture here (PNG)")
    ap.add_argument("--rays", type=int, default=16, help="the reference's rays a pixel, across")
    args = ap.parse_args()
    w, h = (int(v) for v in args.size.split("x"))
    work = tempfile.mkdtemp(prefix="dhdr_texfilter_")
    tool = os.path.join(args.bin, "dhdr-gbuffer")
    subprocess.run(["oiiotool", "--pattern", "checker:width=4:height=4", "256x256", "3", "-d",
                    "uint8", "-o", os.path.join(work, "checker.png")], check=True)
    scene = os.path.join(work, "floor.gltf")
    floor_scene(scene)
    # The 1-sample frames first: a child started by a large Python process reports that
    # process's peak memory as its own.
    half = math.atan(math.tan(math.radians(FOV) / 2) / h)  # half a pixel at the centre
    shots, turned, costs = {}, {}, {}
    for flt in FILTERS:
        shots[flt], _, trace, wall, rss = albedo(tool, scene, work, (w, h), flt)
        turned[flt] = albedo(tool, scene, work, (w, h), flt, yaw=half)[0]
        costs[flt] = (trace, wall, rss)
    s = args.rays
    fine, fine_a, _, _, _ = albedo(tool, scene, work, (w * s, h * s), "bilinear")
    ref = box(fine, s)
    floor = box((fine_a > 0).astype(np.float64), s) == 1.0  # all 256 rays meet the floor
    del fine, fine_a
    ref_t = box(albedo(tool, scene, work, (w * s, h * s), "bilinear", yaw=half)[0], s)
    # Turned half a pixel, pixel x of the turned frame sees between x and x + 1 of the first
    # (the scene moves right): each pair averaged, the frames should agree.
    both = floor[:, :-1] & floor[:, 1:]

    def shimmer(a, b):
        return np.sqrt(np.mean((0.5 * (a[:, :-1] + a[:, 1:]) - b[:, :-1])[both] ** 2))

    print("Checkered floor, %dx%d, %d cores; reference: %dx%d rays a pixel" % (w, h, os.cpu_count(), s, s))
    for flt in FILTERS:
        err = np.sqrt(np.mean((shots[flt] - ref)[floor] ** 2))
        print("%-12s RMS error %.4f  shimmer %.4f  trace %.0f ms  wall %.2f s  peak %.0f MiB"
              % ((flt, err, shimmer(shots[flt], turned[flt])) + costs[flt]))
    print("%-12s                 shimmer %.4f" % ("reference", shimmer(ref, ref_t)))
    if args.picture:
        # Four panels, top left to bottom right: bilinear, trilinear, anisotropic, reference;
        # the far half of the floor, where filtering matters.
        panels = [shots[f] for f in FILTERS] + [ref]
        top = h // 2 - h // 5
        crops = [p[top:top + h // 3, :, :] for p in panels]
        grid = np.concatenate([np.concatenate(crops[:2], axis=1), np.concatenate(crops[2:], axis=1)],
                              axis=0)
        grid = np.clip(grid, 0, 1)
        srgb = np.where(grid <= 0.0031308, 12.92 * grid, 1.055 * grid ** (1 / 2.4) - 0.055)
        out = oiio.ImageBuf(oiio.ImageSpec(grid.shape[1], grid.shape[0], 3, oiio.FLOAT))
        out.set_pixels(oiio.ROI(0, grid.shape[1], 0, grid.shape[0], 0, 1, 0, 3),
                       np.ascontiguousarray(srgb, dtype=np.float32))
        out.write(args.picture, oiio.UINT8)
        print("wrote", args.picture)
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
