#!/usr/bin/env python3
"""Probes against the reference path tracer, per surface: a scene's G-buffer lit direct only,
with probes (+ the specular indirect light, as dhdr-light does by default with --scene) and by
--gi path; the indirect light (frame less direct) as mean luminance per object, and the probes'
relative error. Prints the bake's and each frame's wall time and peak memory.

    /usr/bin/python3 bench/gi_surfaces.py --bin build/apps [--scene testdata/cornell_box.gltf]
        [--size 320x320] [--spp 256] [--spacing 0.1|auto] [--scale 10] [--faces [--bands K]]

--scale S renders a copy of a glTF scene under a root node scaled by S (the Cornell box at 10
is the 5.5 m box Blender exports; its lights' intensities are unchanged). --faces splits each
object with more than one face into its faces (pixels of one shading normal, to 0.05, at least
20 of them), and --bands K each upright face (|N.y| < 0.5) into K bands of height over the
object's height.

Needs OpenImageIO's Python module (python3-openimageio) and numpy.
"""
import argparse
import json
import os
import shutil
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lights import TESTDATA, run  # noqa: E402


def channels(path, names):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    pixels = buf.get_pixels(oiio.FLOAT)
    return [pixels[:, :, spec.channelindex(n)] for n in names], spec


def luminance(path):
    (r, g, b), _ = channels(path, ["R", "G", "B"])
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--scene", default=os.path.join(TESTDATA, "cornell_box.gltf"))
    ap.add_argument("--size", default="320x320")
    ap.add_argument("--spp", default="256")
    ap.add_argument("--spacing", default="0.1", help="probe spacing, or 'auto' for the tool's default")
    ap.add_argument("--scale", type=float, default=1.0, help="scale the glTF scene by this")
    ap.add_argument("--keep", help="keep the images in this folder")
    ap.add_argument("--faces", action="store_true", help="also per face of each object with several")
    ap.add_argument("--bands", type=int, default=1, help="with --faces: height bands per upright face")
    args = ap.parse_args()
    work = args.keep or tempfile.mkdtemp(prefix="dhdr_gi_")
    os.makedirs(work, exist_ok=True)
    tool = lambda name: os.path.join(args.bin, name)
    f = lambda name: os.path.join(work, name)
    spacing = [] if args.spacing == "auto" else ["--spacing", args.spacing]
    if args.scale != 1.0:
        with open(args.scene) as fh:
            gltf = json.load(fh)
        scene = gltf["scenes"][gltf.get("scene", 0)]
        gltf["nodes"].append({"name": "dhdr bench scale", "scale": [args.scale] * 3,
                              "children": scene["nodes"]})
        scene["nodes"] = [len(gltf["nodes"]) - 1]
        base_dir = os.path.dirname(os.path.abspath(args.scene))
        for b in gltf.get("buffers", []) + gltf.get("images", []):
            if "uri" in b and not b["uri"].startswith("data:"):
                b["uri"] = os.path.join(base_dir, b["uri"])
        args.scene = f("scaled.gltf")
        with open(args.scene, "w") as fh:
            json.dump(gltf, fh)
    wall, rss, err = run([tool("dhdr-probes"), args.scene, *spacing, "-o", f("p.exr"), "-v"])
    print("bake: %.2f s, %.0f MiB  [%s]" % (wall, rss, [l for l in err.splitlines() if "probes (" in l][-1]))
    run([tool("dhdr-gbuffer"), args.scene, "--size", args.size, "-o", f("g.exr"), "-q"])
    base = [tool("dhdr-light"), f("g.exr"), "--scene", args.scene, "--type", "float"]
    frames = {"direct": ["--gi", "direct", "--specular-samples", "0"],
              "probes": ["--probes", f("p.exr")],
              "path": ["--gi", "path", "--spp", args.spp]}
    for name, extra in frames.items():
        wall, rss, _ = run(base + extra + ["-o", f(name + ".exr")])
        print("%-7s %8.2f s, %5.0f MiB" % (name, wall, rss))
    # OpenImageIO's Python reads a uint channel as float normalised by 2^32 - 1.
    (ids,), spec = channels(f("g.exr"), ["id.object"])
    ids = np.rint(ids.astype(np.float64) * 4294967295.0).astype(np.int64)
    names = spec.getattribute("dhdr:objectNames") or ()
    direct, probes, path = (luminance(f(n + ".exr")) for n in ("direct", "probes", "path"))
    if args.faces:
        (nx, ny, nz, py), _ = channels(f("g.exr"), ["N.X", "N.Y", "N.Z", "P.Y"])
        normal = np.stack([np.rint(nx * 20), np.rint(ny * 20), np.rint(nz * 20)], -1).astype(np.int64)

    def row(label, m):
        a, b = float((probes - direct)[m].mean()), float((path - direct)[m].mean())
        print("%-30s %8d %10.5f %10.5f %+7.1f %%" % (label, m.sum(), a, b, 100.0 * (a / b - 1.0) if b > 0 else 0.0))

    print("%-30s %8s %10s %10s %8s" % ("object", "pixels", "probes", "path", "error"))
    for i in sorted(set(int(v) for v in np.unique(ids)) - {0}):
        m = ids == i
        row(names[i] if i < len(names) else str(i), m)
        if not args.faces:
            continue
        faces = [k for k in np.unique(normal[m], axis=0) if (m & np.all(normal == k, -1)).sum() >= 20]
        if len(faces) < 2:
            continue
        lo, hi = float(py[m].min()), float(py[m].max())
        for k in faces:
            mk = m & np.all(normal == k, -1)
            row("  n = (%+.2f %+.2f %+.2f)" % tuple(k / 20.0), mk)
            if args.bands > 1 and abs(k[1]) < 10:
                for j in range(args.bands):
                    y0, y1 = lo + (hi - lo) * j / args.bands, lo + (hi - lo) * (j + 1) / args.bands
                    band = mk & (py >= y0) & ((py < y1) if j + 1 < args.bands else (py <= y1))
                    if band.sum():
                        row("    y %.2f-%.2f" % (y0, y1), band)
    covered = ids > 0
    a, b = float((probes - direct)[covered].mean()), float((path - direct)[covered].mean())
    print("%-30s %8d %10.5f %10.5f %+7.1f %%" % ("frame", covered.sum(), a, b, 100.0 * (a / b - 1.0)))
    if not args.keep:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
