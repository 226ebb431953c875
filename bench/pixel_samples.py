#!/usr/bin/env python3
"""Several primary rays a pixel (dhdr-gbuffer --pixel-samples, docs/gbuffer.md "Samples and the
pixel filter"): for each scene, the frame lit with one ray a pixel, with one ray and dhdr-aa, and
with N adaptive rays, against the same chain with N × 4 rays in every pixel (the brute-force
path of the same filter): RMS error of the tone-mapped frame (display-referred, 0-1) over all
pixels, over the pixels the adaptive G-buffer gave several rays (and their neighbours) and over the others; wall time and peak
memory of dhdr-gbuffer + dhdr-light (--gi direct: the indirect light is the same for all).

    /usr/bin/python3 bench/pixel_samples.py --bin build/apps [--size 960x540] [--rays 16]
        [--scene testdata/cornell_box.gltf] [--scene /usr/share/assimp/models/glTF2/...]
        [--picture docs/images/pixel_samples.png]
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lights import run  # noqa: E402

ENGINE = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"


SUN = os.path.join(tempfile.gettempdir(), "dhdr-pixel-samples-sun.json")


def chain(bins, scene, size, out, gbuffer_args, aa=False):
    """G-buffer, light, (aa,) tone map: the display-referred frame as floats, seconds, MiB."""
    g, lit = out + ".g.exr", out + ".l.exr"
    frame = [] if "cornell" in scene else ["--frame-all"]
    t1, m1, _ = run([bins + "/dhdr-gbuffer", scene, "--size", size, "-o", g] + frame + gbuffer_args)
    # A scene without lights of its own gets a sun and a fill light.
    lights = [] if "cornell" in scene else ["--lights", SUN]
    t2, m2, _ = run([bins + "/dhdr-light", g, "--scene", scene, "--gi", "direct", "-o", lit,
                     "--type", "float"] + lights)
    if aa:
        run([bins + "/dhdr-aa", lit, "--gbuffer", g, "-o", lit + ".aa.exr"])
        lit += ".aa.exr"
    run([bins + "/dhdr-tonemap", lit, "-o", out + ".png"])
    img = oiio.ImageBuf(out + ".png").get_pixels(oiio.FLOAT)[..., :3]
    return img, t1 + t2, max(m1, m2)


def edges(gbuffer):
    """The pixels the adaptive G-buffer gave several rays (sample.weight < 1), and their
    neighbours: silhouettes, creases, steps and thin things, found from geometry alone."""
    buf = oiio.ImageBuf(gbuffer)
    spec, deep = buf.spec(), buf.deepdata()
    weight = list(spec.channelnames).index("sample.weight")
    d = np.zeros(deep.pixels, bool)
    for p in range(deep.pixels):
        d[p] = deep.samples(p) > 0 and deep.deep_value(p, weight, 0) < 1.0
    d = d.reshape(spec.height, spec.width)
    grown = d.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            grown |= np.roll(np.roll(d, dy, 0), dx, 1)
    return grown


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", default="960x540")
    ap.add_argument("--rays", type=int, default=16)
    ap.add_argument("--scene", action="append")
    ap.add_argument("--picture")
    a = ap.parse_args()
    scenes = a.scene or ["testdata/cornell_box.gltf", ENGINE]
    tmp = tempfile.mkdtemp(prefix="dhdr-pixel-samples-")
    with open(SUN, "w") as f:
        f.write('{"lights": [{"type": "directional", "direction": [-0.4, -1, -0.6], '
                '"intensity": 3.0}, {"type": "ambient", "intensity": 0.3}]}')
    print("| scene | frame | RMS all | RMS edges | RMS elsewhere | G-buffer + light | peak |")
    print("|---|---|---|---|---|---|---|")
    for scene in scenes:
        if not os.path.exists(scene):
            print("| %s | missing | | | | | |" % scene)
            continue
        name = os.path.basename(scene)
        ref_rays = min(64, a.rays * 4)
        ref, _, _ = chain(a.bin, scene, a.size, os.path.join(tmp, "ref"),
                          ["--pixel-samples", str(ref_rays), "--pixel-sampling", "all"])
        frames = {}
        for label, args, aa in (("one ray", ["--pixel-samples", "1"], False),
                                ("one ray + dhdr-aa", ["--pixel-samples", "1"], True),
                                ("%d adaptive" % a.rays, ["--pixel-samples", str(a.rays)], False)):
            frames[label] = chain(a.bin, scene, a.size, os.path.join(tmp, "f"), args, aa)
        mask = edges(os.path.join(tmp, "f.g.exr"))  # the last chain's: the adaptive one
        for label, (img, seconds, mib) in frames.items():
            e = (img - ref) ** 2
            rms = lambda m: float(np.sqrt(e[m].mean())) if m.any() else 0.0  # noqa: E731
            print("| %s | %s | %.4f | %.4f | %.4f | %.2f s | %.0f MiB |" % (
                name, label, rms(np.ones(mask.shape, bool)), rms(mask), rms(~mask), seconds, mib))
        print("| %s | reference: %d rays, every pixel | | | (%.1f %% of pixels are edges) | | |" % (
            name, ref_rays, 100.0 * mask.mean()))
        if a.picture and scene == scenes[0]:
            # The window of the most edge pixels, magnified 4×.
            h, w = ref.shape[:2]
            ch, cw = h // 6, w // 8
            best = max(((mask[y:y + ch, x:x + cw].sum(), y, x) for y in range(0, h - ch, 8)
                        for x in range(0, w - cw, 8)))
            crop = lambda img: img[best[1]:best[1] + ch, best[2]:best[2] + cw]  # noqa: E731
            tiles = [crop(frames["one ray"][0]), crop(frames["one ray + dhdr-aa"][0]),
                     crop(frames["%d adaptive" % a.rays][0]), crop(ref)]
            gap = np.ones((ch * 4, 4, 3))
            row = np.concatenate(sum(([np.kron(t, np.ones((4, 4, 1))), gap] for t in tiles), [])[:-1],
                                 axis=1)
            out = oiio.ImageBuf(oiio.ImageSpec(row.shape[1], row.shape[0], 3, "float"))
            out.set_pixels(oiio.ROI(), row.astype(np.float32))
            out.write(a.picture, "uint8")
    subprocess.run(["rm", "-rf", tmp])


if __name__ == "__main__":
    main()
