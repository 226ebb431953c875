#!/usr/bin/env python3
"""Light probes in the open (issue 46): testdata/spheres.gltf on a shadow-catching ground plane
under each of blender-data's eight HDRIs, lit by dhdr-light without probes (what --gi auto
does under an environment) and with the probes dhdr-probes bakes for the scene and the same
environment. Prints, per HDRI, the catcher's mean shadow alpha and the objects' mean
luminance both ways and their change, and the bake's time. Goal (issue 46): the frame with
probes within 2 % of the frame without them plus the bounce light; today it is not, which is
why --gi auto bakes no probes under an environment light.

    python3 bench/open_scene.py --bin build/apps [--size 320x180] [--hdri city,forest]
"""
import argparse
import os
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lights import TESTDATA, run  # noqa: E402

WORLD = "/usr/share/blender/datafiles/studiolights/world"


def channels(path, names):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    px = buf.get_pixels(oiio.FLOAT)
    return [px[..., spec.channelindex(n)] for n in names]


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--size", default="320x180")
    ap.add_argument("--hdri", default="", help="comma-separated names (default: all eight)")
    args = ap.parse_args()
    if not os.path.isdir(WORLD):
        sys.exit("open_scene.py: %s is missing (apt-get install blender-data)" % WORLD)
    names = args.hdri.split(",") if args.hdri else sorted(
        f[:-4] for f in os.listdir(WORLD) if f.endswith(".exr"))
    work = tempfile.mkdtemp(prefix="dhdr_open_")
    tool = lambda name: os.path.join(args.bin, name)
    f = lambda name: os.path.join(work, name)
    scene = os.path.join(TESTDATA, "spheres.gltf")
    run([tool("dhdr-gbuffer"), scene, "--size", args.size, "--ground-plane", "-o", f("g.exr"), "-q"])
    ids, alpha = channels(f("g.exr"), ["id.object", "A"])
    spec = oiio.ImageBuf(f("g.exr")).spec()
    objects = list(spec.getattribute("dhdr:objectNames") or ())
    ids = np.rint(ids.astype(np.float64) * 4294967295.0).astype(np.int64)
    ground = ids == objects.index("dhdr:ground plane") if "dhdr:ground plane" in objects else ids < 0
    solid = (ids > 0) & ~ground
    print("Probes in the open: spheres on a catcher, %s, %d cores" % (args.size, os.cpu_count()))
    print("%-10s %9s %9s %8s %10s %10s %8s %7s" % ("HDRI", "alpha", "+probes", "change", "objects",
                                                   "+probes", "change", "bake s"))
    for name in names:
        with open(f(name + ".json"), "w") as out:
            out.write('{"lights": [{"type": "environment", "image": "%s/%s.exr"}]}' % (WORLD, name))
        lights = ["--lights", f(name + ".json")]
        wall, _, _ = run([tool("dhdr-probes"), scene, *lights, "-o", f(name + ".probes.exr"), "-q"])
        frames = {}
        for kind, extra in [("off", []), ("on", ["--probes", f(name + ".probes.exr")])]:
            run([tool("dhdr-light"), f("g.exr"), "--scene", scene, *lights, *extra, "--type",
                 "float", "-q", "-o", f(name + kind + ".exr")])
            r, g, b, a = channels(f(name + kind + ".exr"), ["R", "G", "B", "A"])
            lum = 0.2126 * r + 0.7152 * g + 0.0722 * b
            frames[kind] = (float(a[ground].mean()), float(lum[solid].mean()))
        (a0, l0), (a1, l1) = frames["off"], frames["on"]
        print("%-10s %9.4f %9.4f %+7.1f%% %10.4f %10.4f %+7.1f%% %7.2f"
              % (name, a0, a1, 100 * (a1 / a0 - 1) if a0 else 0.0, l0, l1,
                 100 * (l1 / l0 - 1) if l0 else 0.0, wall))


if __name__ == "__main__":
    main()
