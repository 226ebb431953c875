#!/usr/bin/env python3
"""Many small emitters: ClearCoatTest's nine glowing labels (each an emissive-mesh light) lit
with each light's own shadow rays (--light-budget 0, the exhaustive path) and with the default
shared budget, against the frame without the labels (their emission zeroed in a copy of the
glTF). Prints wall and CPU time (best of --repeats), the shading stage's time (dhdr-light -v), peak
memory (GNU time, as bench/lights.py), shadow rays per G-buffer sample and noise: the RMS error of RGB over the covered pixels against a
reference of each light's own --ref-samples rays, relative to the reference's mean.

Without the labels the scene has no light, so every frame here but "as shipped" adds a sun
(directional, 2° wide: soft shadows of its own) from a lights file.

    python3 bench/many_emitters.py --bin build/apps [--size 960x540] [--repeats 3]
        [--docs-picture docs/images/many_emitters.png]

--docs-picture composes the labels as shipped, each its own rays and shared, and each one's
error against the reference (x2), cropped to the objects (docs/lighting.md#many-emitters).
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import OpenImageIO as oiio

TIME = "/usr/bin/time"  # Debian's `time`


def run(cmd):
    """Runs `cmd` under GNU time: its wall time (s), CPU time (user + system, s: steadier than
    the wall time on a machine shared with other work), peak memory (MiB) and stderr."""
    full = [TIME, "-f", "dhdr-bench %M %U %S"] + cmd
    start = time.perf_counter()
    proc = subprocess.run(full, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    wall = time.perf_counter() - start
    lines = proc.stderr.decode().rstrip("\n").split("\n")
    if proc.returncode != 0 or not lines[-1].startswith("dhdr-bench "):
        sys.exit("bench: %s failed:\n%s" % (" ".join(cmd), "\n".join(lines)))
    kib, user, system = lines[-1].split()[1:]
    return wall, float(user) + float(system), int(kib) / 1024.0, "\n".join(lines[:-1])

MODEL = "/usr/share/assimp/models/glTF2/ClearCoat-glTF/ClearCoatTest.gltf"
SUN = {"lights": [{"type": "directional", "direction": [0.3, -0.4, -1.0], "intensity": 2.0,
                   "angle": 2.0}]}


def pixels(path):
    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)


def noise(path, reference):
    ref = pixels(reference)
    covered = ref[..., 3] > 0
    d = (pixels(path)[..., :3] - ref[..., :3])[covered]
    return float(np.sqrt((d ** 2).mean()) / ref[..., :3][covered].mean())


def docs_picture(work, png):
    ref = pixels(os.path.join(work, "ref_shipped.exr"))
    frames = [pixels(os.path.join(work, f)) for f in ("shipped_all.exr", "shipped_shared.exr")]
    x0, x1, y0, y1 = 440, 660, 75, 445  # the objects, at 960 x 540
    covered = ref[..., 3] > 0
    # One exposure for every panel: the reference's log-average to 0.18, Reinhard, sRGB.
    scale = 0.18 / np.exp(np.log(1e-4 + ref[..., :3].mean(-1)[covered]).mean())

    def tone(img):
        v = img[..., :3] * scale
        v = v / (1.0 + v)
        return np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1 / 2.4) - 0.055)

    def error(img):
        e = np.abs(img[..., :3] - ref[..., :3]).mean(-1, keepdims=True) * (2.0 * scale)
        return np.repeat(np.clip(e, 0.0, 1.0), 3, -1)

    panels = [tone(f) for f in frames] + [error(f) for f in frames]
    names = ["each label its own 16 rays", "shared: 32 rays a pixel (default)",
             "|error| x2, each its own", "|error| x2, shared"]
    w, top, gap = x1 - x0, 24, 4
    canvas = np.ones((y1 - y0 + top, 4 * w + 3 * gap, 3), np.float32)
    for i, p in enumerate(panels):
        canvas[top:, i * (w + gap):i * (w + gap) + w] = p[y0:y1, x0:x1]
    buf = oiio.ImageBuf(oiio.ImageSpec(canvas.shape[1], canvas.shape[0], 3, oiio.FLOAT))
    buf.set_pixels(oiio.ROI(), canvas)
    for i, n in enumerate(names):
        oiio.ImageBufAlgo.render_text(buf, i * (w + gap) + 4, 17, n, 13, "DejaVuSans", (0, 0, 0))
    if not buf.write(png, "uint8"):
        sys.exit("bench: %s: %s" % (png, buf.geterror()))


def rays_per_sample(err):
    m = re.search(r"(\d+) samples over \d+ covered pixels; (\d+) shadow rays", err)
    if not m:
        m = re.search(r"(\d+) covered pixels; (\d+) shadow rays", err)
    return int(m.group(2)) / int(m.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/apps")
    ap.add_argument("--model", default=MODEL)
    ap.add_argument("--size", default="960x540")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--ref-samples", type=int, default=512)
    ap.add_argument("--keep", help="keep the frames in this folder")
    ap.add_argument("--docs-picture", metavar="PNG", help="compose docs/images/many_emitters.png")
    a = ap.parse_args()
    tool = lambda name: os.path.join(a.bin, name)  # noqa: E731
    work = a.keep or tempfile.mkdtemp(prefix="dhdr-many-")
    os.makedirs(work, exist_ok=True)
    src = os.path.dirname(os.path.abspath(a.model))
    for f in os.listdir(src):  # the model's buffers and textures beside the copies
        if not os.path.exists(os.path.join(work, f)):
            os.symlink(os.path.join(src, f), os.path.join(work, f))
    with open(a.model) as f:
        doc = json.load(f)
    labels = os.path.join(work, "labels.gltf")
    plain = os.path.join(work, "no_labels.gltf")
    with open(labels, "w") as f:
        json.dump(doc, f)
    for m in doc["materials"]:
        m.pop("emissiveTexture", None)
        m["emissiveFactor"] = [0.0, 0.0, 0.0]
    with open(plain, "w") as f:
        json.dump(doc, f)
    sun = os.path.join(work, "sun.json")
    with open(sun, "w") as f:
        json.dump(SUN, f)
    for scene in (labels, plain):
        run([tool("dhdr-gbuffer"), scene, "--frame-all", "--size", a.size,
             "-o", scene + ".gbuf.exr"])

    def light(scene, out, *options):
        return [tool("dhdr-light"), scene + ".gbuf.exr", "--scene", scene, "--gi", "direct",
                "-v", "-o", os.path.join(work, out)] + list(options)

    references = {
        "shipped": light(labels, "ref_shipped.exr", "--light-budget", "0",
                         "--shadow-samples", str(a.ref_samples)),
        "sun": light(labels, "ref_sun.exr", "--lights", sun, "--light-budget", "0",
                     "--shadow-samples", str(a.ref_samples)),
        "plain": light(plain, "ref_plain.exr", "--lights", sun,
                       "--shadow-samples", str(a.ref_samples)),
    }
    for cmd in references.values():
        run(cmd)
    rows = [
        ("labels as shipped", "exhaustive (--light-budget 0)", "shipped",
         light(labels, "shipped_all.exr", "--light-budget", "0")),
        ("labels as shipped", "shared (default)", "shipped", light(labels, "shipped_shared.exr")),
        ("sun + labels", "exhaustive (--light-budget 0)", "sun",
         light(labels, "sun_all.exr", "--lights", sun, "--light-budget", "0")),
        ("sun + labels", "shared (default)", "sun",
         light(labels, "sun_shared.exr", "--lights", sun)),
        ("sun, labels off", "default", "plain", light(plain, "plain.exr", "--lights", sun)),
    ]
    print("frame %s, best of %d; noise: RMS error / mean against %d rays a light"
          % (a.size, a.repeats, a.ref_samples))
    print("| frame | path | wall s | CPU s | shade s | peak MiB | shadow rays / sample | noise |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for frame, path, ref, cmd in rows:
        wall, cpu, shade, peak, err = [], [], [], 0.0, ""
        for _ in range(a.repeats):
            w, c, mem, err = run(cmd)
            wall.append(w)
            cpu.append(c)
            shade.append(float(re.search(r"shade (\d+) ms", err).group(1)) / 1000.0)
            peak = max(peak, mem)
        out = cmd[cmd.index("-o") + 1]
        print("| %s | %s | %.2f | %.2f | %.2f | %.0f | %.1f | %.4f |"
              % (frame, path, min(wall), min(cpu), min(shade), peak, rays_per_sample(err),
                 noise(out, os.path.join(work, "ref_%s.exr" % ref))))
    if a.docs_picture:
        docs_picture(work, a.docs_picture)
    if not a.keep:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
