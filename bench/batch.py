#!/usr/bin/python3
"""Batch tone mapping, EXR in and PNG out (issue 47): dhdr-tonemap against oiiotool and a
baseline dhdr-tonemap (another commit's build), on noisy rendered-like frames.

Frames: half RGBA ZIP, a gradient times per-pixel Monte Carlo noise (the mean of a few
exponential samples, with rare fireflies), made once with numpy and OpenImageIO into WORK.

Reports: frames a second of a 1080p sequence (--frames, default operator, 8-bit PNG), the
whole process on one 4K frame (the tools timed alternately, the median of --runs), start-up
(`--version`), peak memory (GNU time's maximum resident set), output sizes, whether the
pixels equal the baseline's, and floors computed from the parts measured on one core:
decode (OpenImageIO reading the EXR as float), encode (libdeflate level 1 on the PNG's
rows, through ctypes) and map (the rest of a one-thread run, start-up taken out).

    bench/batch.py --tonemap build/apps/dhdr-tonemap --baseline /tmp/base/dhdr-tonemap
    bench/batch.py ... --huge     # also a 16K frame, for memory (streamed in strips)
"""
import argparse
import ctypes
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import OpenImageIO as oiio


def noisy_rows(w, y0, y1, seed, spp=4):
    """Rows [y0, y1) of a frame: a smooth gradient times per-pixel Monte Carlo noise."""
    rng = np.random.default_rng([seed, y0])
    y, x = np.mgrid[y0:y1, 0:w].astype(np.float32)
    h = 1080.0
    base = np.stack([0.2 + 1.5 * x / w, 0.3 + 0.8 * y / h,
                     0.5 + 0.5 * np.sin(x / 97 + y / 53 + seed * 0.1)], -1)
    n = rng.gamma(spp, 1.0 / spp, size=(y1 - y0, w, 1)).astype(np.float32)
    rgb = base * n * (1 + 0.15 * rng.standard_normal((y1 - y0, w, 3)).astype(np.float32))
    fireflies = rng.random((y1 - y0, w)) < 0.0005
    rgb[fireflies] *= 50
    rgba = np.concatenate([np.maximum(rgb, 0), np.ones((y1 - y0, w, 1), np.float32)], -1)
    return rgba.astype(np.float16)


def make_frame(path, w, h, seed):
    if os.path.exists(path):
        return
    spec = oiio.ImageSpec(w, h, 4, "half")
    spec.attribute("compression", "zip")
    out = oiio.ImageOutput.create(path)
    tmp = path + ".part.exr"
    out.open(tmp, spec)
    band = 256  # rows at a time, so that a 16K frame needs little memory here
    for y0 in range(0, h, band):
        y1 = min(h, y0 + band)
        out.write_scanlines(y0, y1, 0, noisy_rows(w, y0, y1, seed))
    out.close()
    os.rename(tmp, path)


def timed(cmd):
    """Wall seconds, CPU seconds and peak resident MB of `cmd` under GNU time."""
    t = time.perf_counter()
    r = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t
    if r.returncode != 0:
        sys.exit("failed: " + " ".join(cmd) + "\n" + r.stderr[-2000:])
    user = float(re.search(r"User time \(seconds\): ([\d.]+)", r.stderr).group(1))
    system = float(re.search(r"System time \(seconds\): ([\d.]+)", r.stderr).group(1))
    peak = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", r.stderr).group(1))
    return wall, user + system, peak / 1024.0


def stored(path):
    img = oiio.ImageInput.open(path)
    pixels = img.read_image(img.spec().format)
    img.close()
    return pixels


def decode_seconds(path):
    """CPU seconds OpenImageIO takes to read `path` as float on one thread (no start-up)."""
    oiio.attribute("threads", 1)
    oiio.attribute("exr_threads", 1)
    t = time.process_time()
    buf = oiio.ImageBuf(path)
    buf.read(0, 0, True, oiio.FLOAT)
    return time.process_time() - t


def encode_seconds(png):
    """libdeflate level 1 on the PNG's unfiltered rows, one thread: its encode floor."""
    lib = ctypes.CDLL("libdeflate.so.0")
    lib.libdeflate_alloc_compressor.restype = ctypes.c_void_p
    lib.libdeflate_zlib_compress.restype = ctypes.c_size_t
    lib.libdeflate_zlib_compress.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t,
                                             ctypes.c_void_p, ctypes.c_size_t]
    lib.libdeflate_free_compressor.argtypes = [ctypes.c_void_p]
    pixels = stored(png)
    h = pixels.shape[0]
    rows = np.ascontiguousarray(
        np.concatenate([np.zeros((h, 1), np.uint8), pixels.reshape(h, -1)], 1))
    out = np.empty(rows.nbytes + rows.nbytes // 8 + 1024, np.uint8)
    c = lib.libdeflate_alloc_compressor(1)
    t = time.process_time()
    lib.libdeflate_zlib_compress(c, rows.ctypes.data, rows.nbytes, out.ctypes.data, out.nbytes)
    seconds = time.process_time() - t
    lib.libdeflate_free_compressor(c)
    return seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tonemap", default="build/apps/dhdr-tonemap")
    ap.add_argument("--baseline", help="another build's dhdr-tonemap (the commit before)")
    ap.add_argument("--work", default=os.path.join(tempfile.gettempdir(), "dhdr-bench-batch"))
    ap.add_argument("--frames", type=int, default=24, help="1080p frames in the sequence")
    ap.add_argument("--runs", type=int, default=3, help="runs of each whole-process timing")
    ap.add_argument("--huge", action="store_true", help="also a 16384x8640 frame (memory)")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    w = lambda name: os.path.join(a.work, name)
    for f in range(1, a.frames + 1):
        make_frame(w("hd.%04d.exr" % f), 1920, 1080, f)
    make_frame(w("uhd.exr"), 3840, 2160, 100)
    tools = [("dhdr-tonemap", a.tonemap)] + ([("baseline", a.baseline)] if a.baseline else [])
    print("load average at start: %.1f %.1f %.1f (2 cores)" % os.getloadavg())

    print("\n1080p sequence, %d frames, one process (frames/s; CPU s; peak MB; PNG MB)" % a.frames)
    for name, exe in tools:
        runs = [timed([exe, w("hd.####.exr"), "--frames", "1-%d" % a.frames,
                       "-o", w(name + ".hd.####.png")]) for _ in range(a.runs)]
        wall = statistics.median(r[0] for r in runs)
        size = sum(os.path.getsize(w(name + ".hd.%04d.png" % f)) for f in range(1, a.frames + 1))
        print("  %-13s %6.2f frames/s  %6.2f CPU s  %6.0f MB  %8.2f MB" %
              (name, a.frames / wall, statistics.median(r[1] for r in runs),
               max(r[2] for r in runs), size / 1e6))

    print("\n4K frame, whole process, timed alternately (median wall s; CPU s; peak MB; PNG MB)")
    cmds = [(name, [exe, w("uhd.exr"), "-o", w(name + ".uhd.png")]) for name, exe in tools]
    cmds.append(("oiiotool", ["oiiotool", w("uhd.exr"), "-d", "uint8", "-o", w("oiio.uhd.png")]))
    results = {name: [] for name, _ in cmds}
    for _ in range(a.runs):
        for name, cmd in cmds:
            results[name].append(timed(cmd))
    oiio_wall = statistics.median(r[0] for r in results["oiiotool"])
    for name, _ in cmds:
        rs = results[name]
        wall = statistics.median(r[0] for r in rs)
        png = w(("oiio" if name == "oiiotool" else name) + ".uhd.png")
        print("  %-13s %6.2f s (%.2fx oiiotool)  %6.2f CPU s  %6.0f MB  %6.2f MB" %
              (name, wall, wall / oiio_wall, statistics.median(r[1] for r in rs),
               max(r[2] for r in rs), os.path.getsize(png) / 1e6))

    print("\nstart-up, --version (median wall s; CPU s; peak MB)")
    startup = {}
    for name, exe in tools + [("oiiotool", "oiiotool")]:
        rs = [timed([exe, "--version"]) for _ in range(a.runs)]
        startup[name] = statistics.median(r[1] for r in rs)
        print("  %-13s %6.3f s  %6.3f CPU s  %6.0f MB" %
              (name, statistics.median(r[0] for r in rs), startup[name], max(r[2] for r in rs)))

    if a.baseline:
        same = all(np.array_equal(stored(w("dhdr-tonemap.hd.%04d.png" % f)),
                                  stored(w("baseline.hd.%04d.png" % f)))
                   for f in range(1, a.frames + 1))
        same = same and np.array_equal(stored(w("dhdr-tonemap.uhd.png")),
                                       stored(w("baseline.uhd.png")))
        print("\npixels equal to the baseline's (every frame, and the 4K one): %s" % same)

    print("\nfloors from the parts, one core each (CPU s a frame)")
    for label, exr, png, size in [("1080p", w("hd.0001.exr"), w("dhdr-tonemap.hd.0001.png"),
                                   "hd"), ("4K", w("uhd.exr"), w("dhdr-tonemap.uhd.png"), "uhd")]:
        decode = min(decode_seconds(exr) for _ in range(a.runs))
        encode = min(encode_seconds(png) for _ in range(a.runs))
        one = min(timed([a.tonemap, exr, "--threads", "1", "-o", w("one." + size + ".png")])[1]
                  for _ in range(a.runs))
        mapping = max(0.0, one - startup["dhdr-tonemap"] - decode - encode)
        parts = decode + mapping + encode
        print("  %-5s decode %.3f  map %.3f  encode %.3f  (one-thread run %.3f, start-up %.3f)"
              % (label, decode, mapping, encode, one, startup["dhdr-tonemap"]))
        print("        floor on 2 cores: %.1f frames/s in a sequence; %.2f s for one frame's "
              "process" % (2.0 / parts, startup["dhdr-tonemap"] + parts / 2.0))

    if a.huge:
        make_frame(w("huge.exr"), 16384, 8640, 200)
        print("\n16384x8640 frame (wall s; CPU s; peak MB)")
        for name, exe in tools:
            r = timed([exe, w("huge.exr"), "-o", w(name + ".huge.png")])
            print("  %-13s %6.2f s  %6.2f CPU s  %6.0f MB  %7.1f MB PNG" %
                  (name, r[0], r[1], r[2], os.path.getsize(w(name + ".huge.png")) / 1e6))


if __name__ == "__main__":
    main()
