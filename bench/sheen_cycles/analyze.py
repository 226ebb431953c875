"""python3 analyze.py DHDR_GBUF.exr DHDR_LIT.exr CYCLES.exr: per sphere (dhdr's id.object, interior
pixels that both renderers cover) the mean RGB of each, their ratio, and each sphere's mean over
the sheen-less sphere's (the sheen's gain) in each renderer."""
import sys
import numpy as np
import OpenImageIO as oiio


def channels(path, names):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    px = buf.get_pixels(oiio.FLOAT)
    return [px[..., spec.channelindex(n)] for n in names]


ident, cover = channels(sys.argv[1], ["id.object", "A"])
ident = np.rint(ident * 4294967295.0)  # a uint channel read as float is normalized
dhdr = np.stack(channels(sys.argv[2], ["R", "G", "B"]), -1)
cyc_r, cyc_g, cyc_b, cyc_a = channels(sys.argv[3], ["R", "G", "B", "A"])
cyc = np.stack([cyc_r, cyc_g, cyc_b], -1)
# Interior: covered in both, and not next to an edge (silhouettes differ by a pixel's coverage).
inside = (cover == 1) & (cyc_a > 0.999)
for axis in (0, 1):
    for step in (1, -1):
        inside &= np.roll(ident, step, axis) == ident
print("sphere  sheen  rough   dhdr (R G B)               Cycles (R G B)             dhdr/Cycles (G)  gain dhdr  gain Cycles")
base_d = base_c = None
names = [(c, 0.5) for c in (0.0, 0.25, 0.5, 0.75, 1.0)] + [(1.0, r) for r in (0.1, 0.3, 0.5, 0.7, 1.0)]
for k in range(10):
    m = inside & (ident == k + 1)
    d, c = dhdr[m].mean(0), cyc[m].mean(0)
    if k == 0:
        base_d, base_c = d, c
    print("%6d  %5.2f  %5.2f   %.4f %.4f %.4f   %.4f %.4f %.4f   %.3f            %.3f      %.3f" % (
        k, names[k][0], names[k][1], *d, *c, d[1] / c[1], d[1] / base_d[1], c[1] / base_c[1]))
