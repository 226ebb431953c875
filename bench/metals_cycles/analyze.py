#!/usr/bin/python3
# analyze.py WORK_DIR MATERIAL HDRI [PNG]  (run.sh calls it; needs python3-openimageio, numpy)
# dhdr's environment lighting of five spheres (roughness 0 ... 1) against Cycles, per sphere:
# mean(dhdr)/mean(Cycles) of the luminance (and per channel), the 95th percentile of the per-pixel
# relative error |dhdr/Cycles - 1| of the luminance, Cycles' own noise at that percentile (two
# seeds), and the luminance ratio over grazing (N.V < 0.3), facing (N.V > 0.8) and sun-dominated
# pixels (the sun alone gives more than half of dhdr's pixel), for each --env-specular mode.
# With PNG, writes dhdr (auto) | Cycles | signed difference (red: dhdr brighter, blue: darker, full at 25 %).
import numpy as np, OpenImageIO as oiio, sys
D, mat, hdri = sys.argv[1].rstrip("/") + "/", sys.argv[2], sys.argv[3]
png = sys.argv[4] if len(sys.argv) > 4 else None
MODES = ["split-sum", "quadrature", "auto", "auto-sunkept"]
NAMES = ["r=0", "r=0.25", "r=0.5", "r=0.75", "r=1"]
LUM = np.array([0.2126, 0.7152, 0.0722])

def chans(path, names, fmt=oiio.FLOAT):
    inp = oiio.ImageInput.open(D + path)
    if inp is None: raise SystemExit(f"cannot open {D + path}: {oiio.geterror()}")
    spec = inp.spec(); cn = list(spec.channelnames); out = []
    for n in names:
        i = cn.index(n)
        out.append(inp.read_image(0, 0, i, i + 1, fmt)[:, :, 0].astype(np.float64))
    inp.close(); return out, spec
rgb = lambda p, pre="": np.stack(chans(p, [pre + c for c in "RGB"])[0], -1)

g = f"g_{mat}.exr"
(obj,), gspec = chans(g, ["id.object"], oiio.UINT32)
N = np.stack(chans(g, ["N.X", "N.Y", "N.Z"])[0], -1)
N /= np.maximum(np.linalg.norm(N, axis=-1, keepdims=True), 1e-9)
P = np.stack(chans(g, ["P.X", "P.Y", "P.Z"])[0], -1)
eye = np.array(gspec.getattribute("dhdr:cameraPosition"), dtype=np.float64)
V = eye - P; V /= np.maximum(np.linalg.norm(V, axis=-1, keepdims=True), 1e-9)
NV = (N * V).sum(-1)
dh = {m: rgb(f"d_{mat}_{hdri}_{m}.exr") for m in MODES}
sun = rgb(f"d_{mat}_{hdri}_sun.exr")
c1, c2 = rgb(f"cy_{mat}_{hdri}_s1.exr", "ViewLayer.Combined."), rgb(f"cy_{mat}_{hdri}_s2.exr", "ViewLayer.Combined.")
cy = 0.5 * (c1 + c2)
cyid = np.rint(chans(f"cy_{mat}_{hdri}_s1.exr", ["ViewLayer.IndexOB.X"])[0][0]).astype(int)
L = lambda x: x @ LUM
cyL, nL = L(cy), np.abs(L(c1) - L(c2)) / np.maximum(L(c1) + L(c2), 1e-12)   # relative noise of the mean
sunshare = L(sun) / np.maximum(L(dh["auto"]), 1e-12)

def blur3(x, m):   # 3x3 box mean over the sphere's own pixels (m): removes most of Cycles' noise, keeps dhdr's streaks
    w = np.zeros(m.shape); a = np.zeros(m.shape); xm = np.where(m, x, 0.0)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            a += np.roll(np.roll(xm, dy, 0), dx, 1); w += np.roll(np.roll(m.astype(float), dy, 0), dx, 1)
    return a / np.maximum(w, 1)

def erode(m):
    o = m.copy(); o[1:] &= m[:-1]; o[:-1] &= m[1:]; o[:, 1:] &= m[:, :-1]; o[:, :-1] &= m[:, 1:]
    return o
iou = [((obj == k) & (cyid == k)).sum() / max(((obj == k) | (cyid == k)).sum(), 1) for k in range(1, 6)]
print(f"\n[{mat} / {hdri}] masks dhdr vs Cycles IoU: " + " ".join(f"{v:.3f}" for v in iou))
print(f"{'sphere':7s} {'mode':10s} {'n':>5s} {'Cycles Y':>8s} {'Y ratio':>7s} {'R':>6s} {'G':>6s} {'B':>6s}"
      f" {'p95|err|':>8s} {'(noise)':>7s} {'p95 3x3':>7s} {'(noise)':>7s} {'graz':>6s} {'face':>6s} {'sun':>6s}  (n graz/face/sun)")
rows = []
for k in range(1, 6):
    m = erode((obj == k) & (cyid == k)) & (cyL > 1e-6)
    gz, fc, sn = m & (NV < 0.3), m & (NV > 0.8), m & (sunshare > 0.5)
    noise95 = np.percentile(nL[m], 95)
    full = (obj == k) & (cyid == k)
    b1, b2 = blur3(L(c1), full), blur3(L(c2), full); cyB = 0.5 * (b1 + b2)
    noiseB = np.percentile(np.abs(b1 - b2)[m] / np.maximum(b1 + b2, 1e-12)[m], 95)
    for mode in MODES:
        d = dh[mode]; dL = L(d)
        ratio = dL[m].mean() / cyL[m].mean()
        ch = d[m].mean(0) / cy[m].mean(0)
        p95 = np.percentile(np.abs(dL[m] / cyL[m] - 1), 95)
        p95b = np.percentile(np.abs(blur3(dL, full)[m] / cyB[m] - 1), 95)
        sub = lambda s: f"{dL[s].mean() / cyL[s].mean():6.3f}" if s.sum() >= 5 else f"{'-':>6s}"
        print(f"{NAMES[k-1]:7s} {mode:10s} {int(m.sum()):5d} {cyL[m].mean():8.4f} {ratio:7.3f} {ch[0]:6.3f} {ch[1]:6.3f} {ch[2]:6.3f}"
              f" {p95:8.3f} {noise95:7.3f} {p95b:7.3f} {noiseB:7.3f} {sub(gz)} {sub(fc)} {sub(sn)}  ({int(gz.sum())}/{int(fc.sum())}/{int(sn.sum())})")
        rows.append(dict(mat=mat, hdri=hdri, sphere=NAMES[k-1], mode=mode, ratio=ratio, rgb=ch.tolist(), p95=p95,
                         noise95=noise95, p95b=p95b, noiseB=noiseB,
                         graz=dL[gz].mean() / cyL[gz].mean(), face=dL[fc].mean() / cyL[fc].mean(),
                         sun=dL[sn].mean() / cyL[sn].mean() if sn.sum() >= 5 else None))
import json
json.dump(rows, open(D + f"rows_{mat}_{hdri}.json", "w"))

if png:
    H, W = obj.shape
    ref = np.percentile(L(cy)[cyL > 0], 99)
    tm = lambda x: np.clip(x / ref, 0, 1) ** (1 / 2.2)
    rel = np.where((obj > 0) & (cyL > 1e-6), L(dh["auto"]) / np.maximum(cyL, 1e-12) - 1, 0)
    t = np.clip(np.abs(rel) / 0.25, 0, 1)[..., None]
    diff = np.where(rel[..., None] > 0, t * np.array([1, 0.1, 0.1]), t * np.array([0.1, 0.3, 1]))
    pad = np.ones((H, 4, 3))
    img = np.concatenate([tm(dh["auto"]), pad, tm(cy), pad, diff], 1).astype(np.float32)
    buf = oiio.ImageBuf(oiio.ImageSpec(img.shape[1], img.shape[0], 3, oiio.FLOAT))
    buf.set_pixels(oiio.ROI(0, img.shape[1], 0, img.shape[0]), img)
    buf.write(png, "uint8")
