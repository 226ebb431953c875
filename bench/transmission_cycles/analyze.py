#!/usr/bin/python3
"""analyze.py WORK_DIR [CYCLES_EXR [DHDR_EXR]]: dhdr (WORK_DIR/dhdr.exr, its deep samples dhdr.deep.exr)
against Cycles (WORK_DIR/cycles.exr) on the scene of cycles_scene.py, per region.

Regions come from casting each pixel's ray (dhdr's and Cycles' pinhole camera: --lookat EYE,TGT,
vertical fov 40) against the scene's analytic shapes (the numbers of cycles_scene.py, in glTF's
Y-up frame): the first hit (a pane or not), what lies behind a pane, and whether that point sees
the sun. Each region is eroded by one pixel and kept only where Cycles' IndexOB and dhdr's front
id.object agree with the cast. A pane's reflection is its own light: in dhdr the front sample of
the deep output (premultiplied: the pane's reflection and its diffuse share, which is 0 at
transmission 1), in Cycles (GlossDir + GlossInd) x GlossCol. Writes WORK_DIR/side_by_side.png
(dhdr left, Cycles right, exposure +0, sRGB)."""
import sys
import numpy as np
import OpenImageIO as oiio

D = sys.argv[1].rstrip("/") + "/"
CY = sys.argv[2] if len(sys.argv) > 2 else D + "cycles.exr"
DH = sys.argv[3] if len(sys.argv) > 3 else D + "dhdr.exr"
W, H, FOV = 320, 240, 40.0
EYE, TGT = np.array([0, 2.0, 4.5]), np.array([0, 0.45, -1.2])
SUN = -np.array([0.35, -1.0, -0.8]); SUN /= np.linalg.norm(SUN)          # towards the sun
PANES = [(-1.2, "A clear r0"), (0.0, "B tint r0"), (1.2, "C clear r0.3")]   # x centres; ids 3, 4, 5
SPHERES = [(-1.2, -1.5, 6), (0.0, -1.5, 7), (1.2, -1.5, 8), (2.3, -1.0, 9)]  # (x, z, id), r 0.3, y 0.3
R = 0.3


def read(path, names):
    inp = oiio.ImageInput.open(path)
    spec = inp.spec(); cn = list(spec.channelnames)
    px = inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT); inp.close()
    return [px[..., cn.index(n)].astype(np.float64) for n in names]


# Camera rays through pixel centres.
f = TGT - EYE; f /= np.linalg.norm(f)
r = np.cross(f, [0, 1, 0]); r /= np.linalg.norm(r); u = np.cross(r, f)
t = np.tan(np.radians(FOV) / 2)
ys, xs = np.mgrid[0:H, 0:W] + 0.5
dirs = (f[None, None] + ((2 * xs / W - 1) * t * W / H)[..., None] * r + ((1 - 2 * ys / H) * t)[..., None] * u)
dirs /= np.linalg.norm(dirs, axis=-1, keepdims=True)
O = np.broadcast_to(EYE, dirs.shape)


def hits(o, d):
    """Distances to each shape along rays o + s d (inf where missed), and the shape ids."""
    out = {}
    with np.errstate(divide="ignore", invalid="ignore"):
        s = -o[..., 1] / d[..., 1]; p = o + s[..., None] * d          # floor y = 0
        out[1] = np.where((s > 1e-4) & (np.abs(p[..., 0]) <= 3) & (p[..., 2] >= -3) & (p[..., 2] <= 0.3), s, np.inf)
        s = (-3 - o[..., 2]) / d[..., 2]; p = o + s[..., None] * d     # wall z = -3
        out[2] = np.where((s > 1e-4) & (np.abs(p[..., 0]) <= 3) & (p[..., 1] >= 0) & (p[..., 1] <= 2.5), s, np.inf)
        s = -o[..., 2] / d[..., 2]; p = o + s[..., None] * d           # panes z = 0
        for k, (x, _) in enumerate(PANES):
            out[3 + k] = np.where((s > 1e-4) & (np.abs(p[..., 0] - x) <= 0.5) & (p[..., 1] >= 0) & (p[..., 1] <= 1.4), s, np.inf)
        for x, z, i in SPHERES:
            oc = o - np.array([x, R, z]); b = (oc * d).sum(-1); c = (oc * oc).sum(-1) - R * R
            disc = b * b - c; s = -b - np.sqrt(np.maximum(disc, 0))
            out[i] = np.where((disc > 0) & (s > 1e-4), s, np.inf)
    ids = np.array(sorted(out)); dist = np.stack([out[i] for i in ids], -1)
    return ids, dist


ids, dist = hits(O, dirs)
first = np.where(np.isinf(dist.min(-1)), 0, ids[dist.argmin(-1)])
s1 = dist.min(-1)
# Behind a pane: continue from past the pane's far face.
P1 = O + np.where(np.isinf(s1), 0, s1 + 0.02)[..., None] * dirs
ids2, dist2 = hits(P1, dirs)
dist2[..., (ids2 >= 3) & (ids2 <= 5)] = np.inf   # the same pane's far face
behind = np.where(np.isinf(dist2.min(-1)), 0, ids2[dist2.argmin(-1)])
s2 = dist2.min(-1)
P2 = P1 + np.where(np.isinf(s2), 0, s2)[..., None] * dirs
vis = np.where(((first >= 3) & (first <= 5))[..., None], P2, O + np.where(np.isinf(s1), 0, s1)[..., None] * dirs)
idsS, distS = hits(vis + 1e-3 * SUN, np.broadcast_to(SUN, dirs.shape))
shadow_by = np.where(np.isinf(distS.min(-1)), 0, idsS[distS.argmin(-1)])

# A pane's mirror ray (its faces are z = const): does it see the lit floor or the sky?
idsM, distM = hits(O + np.where(np.isinf(s1), 0, s1 - 0.01)[..., None] * dirs, dirs * np.array([1, 1, -1]))
mirror_floor = np.isfinite(distM[..., list(idsM).index(1)])

dh = np.stack(read(DH, ["R", "G", "B"]), -1)
(dobj,) = read(D + "g_flat.exr", ["id.object"])
dobj = np.rint(dobj * 4294967295.0) if dobj.max() <= 1.0 else np.rint(dobj)
pre = "ViewLayer."
cy = np.stack(read(CY, [pre + "Combined." + c for c in "RGB"]), -1)
gl = sum(np.stack(read(CY, [pre + p + "." + c for c in "RGB"]), -1) for p in ("GlossDir", "GlossInd"))
gl *= np.stack(read(CY, [pre + "GlossCol." + c for c in "RGB"]), -1)
(cid,) = read(CY, [pre + "IndexOB.X"]); cid = np.rint(cid)

# dhdr's pane reflection: the front sample of the deep output.
dref = np.zeros_like(dh)
inp = oiio.ImageInput.open(D + "dhdr.deep.exr"); dd = inp.read_native_deep_image(); inp.close()
for yx in zip(*np.nonzero((first >= 3) & (first <= 5))):
    p = yx[0] * W + yx[1]
    if dd.samples(p) > 0:
        dref[yx] = [dd.deep_value(p, c, 0) for c in range(3)]


def erode(m):
    o = m.copy(); o[1:] &= m[:-1]; o[:-1] &= m[1:]; o[:, 1:] &= m[:, :-1]; o[:, :-1] &= m[:, 1:]
    return o


agree = (cid == first) & (dobj == first)
regions = []
for k, (x, name) in enumerate(PANES):
    pane = first == 3 + k
    see = pane & ~mirror_floor   # seen through, without the lit floor's mirror image that dhdr leaves out
    regions += [
        (f"pane {name}: wall through it", see & (behind == 2) & (shadow_by == 0), "full"),
        (f"pane {name}: sphere through it", see & (behind == SPHERES[k][2]) & (shadow_by == 0), "full"),
        (f"pane {name}: floor through it, sunlit", see & (behind == 1) & (shadow_by == 0), "full"),
        (f"pane {name}: floor through it, in its shadow", see & (behind == 1) & (shadow_by == 3 + k), "full"),
        (f"pane {name}: its reflection of the sky", pane & ~mirror_floor, "refl"),
        (f"pane {name}: its reflection of the floor", pane & mirror_floor, "refl")]
regions += [("open: wall, sunlit", (first == 2) & (shadow_by == 0), "full"),
            ("open: floor, sunlit", (first == 1) & (shadow_by == 0), "full"),
            ("open: floor in a pane's shadow", (first == 1) & (shadow_by >= 3) & (shadow_by <= 5), "full"),
            ("open: floor in the green sphere's shadow", (first == 1) & (shadow_by == 9), "full"),
            ("open: green sphere", first == 9, "full")]
print(f"{'region':48s} {'px':>5s}  {'dhdr R G B':>22s}  {'Cycles R G B':>22s}  {'dhdr/Cycles (lum)':>8s}")
lum = lambda c: c @ np.array([0.2126, 0.7152, 0.0722])
for name, m, kind in regions:
    m = erode(m & agree) if kind == "full" else erode(m) & (cid == first)
    n = int(m.sum())
    if n < 6:
        print(f"{name:48s} {n:5d}  (too few pixels)"); continue
    a, b = (dref, gl) if kind == "refl" else (dh, cy)
    if kind == "refl" and "r0.3" in name:   # Cycles' rough glass is one closure: its reflection is in Trans*
        print(f"{name:48s} {n:5d}  {a[m].mean(0)[0]:6.4f} {a[m].mean(0)[1]:6.4f} {a[m].mean(0)[2]:6.4f}  (not separable in Cycles)"); continue
    ma, mb = a[m].mean(0), b[m].mean(0)
    print(f"{name:48s} {n:5d}  {ma[0]:6.4f} {ma[1]:6.4f} {ma[2]:6.4f}  {mb[0]:6.4f} {mb[1]:6.4f} {mb[2]:6.4f}  {lum(ma) / lum(mb):8.3f}")

# The checker's contrast through each pane's wall region (the rough pane blurs it in Cycles).
print("checker contrast (std / mean of luminance) on the wall, through each pane and open:")
for k, (x, name) in enumerate(PANES):
    m = erode((first == 3 + k) & (behind == 2) & (shadow_by == 0) & agree)
    if m.sum() > 6:
        print(f"  pane {name:14s} dhdr {lum(dh[m]).std() / lum(dh[m]).mean():.3f}  Cycles {lum(cy[m]).std() / lum(cy[m]).mean():.3f}")
m = erode((first == 2) & (shadow_by == 0) & agree)
print(f"  {'open wall':19s} dhdr {lum(dh[m]).std() / lum(dh[m]).mean():.3f}  Cycles {lum(cy[m]).std() / lum(cy[m]).mean():.3f}")

# Cycles' variants (cycles_scene.py's modes), where rendered: each region's luminance, with dhdr's
# sun-only frame (dhdr_sun.exr) beside the sun-only variant.
import os
variants = [v for v in ("nocaustics", "nomis", "opaquepanes", "sunonly") if os.path.exists(D + f"cycles_{v}.exr")]
if variants:
    print("shadows in Cycles' variants (luminance; dhdr: the frame, and its sun alone):")
    vimg = {v: np.stack(read(D + f"cycles_{v}.exr", [pre + "Combined." + c for c in "RGB"]), -1) for v in variants}
    dsun = np.stack(read(D + "dhdr_sun.exr", ["R", "G", "B"]), -1) if os.path.exists(D + "dhdr_sun.exr") else None
    print(f"  {'region':48s} {'dhdr':>7s} {'dhdr sun':>8s} {'Cycles':>7s} " + " ".join(f"{v:>11s}" for v in variants))
    for name, m, kind in regions:
        if "shadow" not in name and "open: floor, sunlit" not in name:
            continue
        m = erode(m & agree)
        if m.sum() < 6:
            continue
        ds = f"{lum(dsun[m].mean(0)):8.4f}" if dsun is not None else f"{'':8s}"
        # Seen through a pane, the opaque (black) panes' variant shows the pane, not the floor.
        print(f"  {name:48s} {lum(dh[m].mean(0)):7.4f} {ds} {lum(cy[m].mean(0)):7.4f} " +
              " ".join(f"{'-':>11s}" if v == "opaquepanes" and name.startswith("pane")
                       else f"{lum(vimg[v][m].mean(0)):11.4f}" for v in variants))

# Side by side, sRGB.
def srgb(c):
    c = np.clip(c, 0, 1)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
both = np.concatenate([srgb(dh), np.ones((H, 4, 3)), srgb(cy)], 1).astype(np.float32)
out = oiio.ImageBuf(oiio.ImageSpec(both.shape[1], H, 3, oiio.FLOAT)); out.set_pixels(oiio.ROI(), both)
out.write(D + "side_by_side.png", oiio.UINT8)
