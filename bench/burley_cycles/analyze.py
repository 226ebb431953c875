#!/usr/bin/python3
# analyze.py WORK_DIR CONFIG SUN_DIR_X,Y,Z  (run.sh calls it; needs python3-openimageio, numpy)
# dhdr's diffuse layer (frame less the black-albedo frame) against Cycles' DiffDir x DiffCol, per
# object, over its lit pixels, its grazing (N.V < 0.3) and its facing (N.V > 0.8) ones.
import numpy as np, OpenImageIO as oiio, sys
D, cfg = sys.argv[1].rstrip("/") + "/", sys.argv[2]
Ldir = -np.array([float(v) for v in sys.argv[3].split(",")]); Ldir /= np.linalg.norm(Ldir)  # towards the sun

def chans(path, names, fmt=oiio.FLOAT):
    inp = oiio.ImageInput.open(D + path); spec = inp.spec(); cn = list(spec.channelnames)
    out = []
    for n in names:
        i = cn.index(n)
        out.append(inp.read_image(0, 0, i, i + 1, fmt)[:, :, 0].astype(np.float64))
    inp.close(); return out, spec
rgb = lambda p, pre="": np.mean(chans(p, [pre + c for c in "RGB"])[0], axis=0)

(obj,), gspec = chans(f"g_{cfg}.exr", ["id.object"], oiio.UINT32)
N = np.stack(chans(f"g_{cfg}.exr", ["N.X", "N.Y", "N.Z"])[0], -1)
N /= np.maximum(np.linalg.norm(N, axis=-1, keepdims=True), 1e-9)
P = np.stack(chans(f"g_{cfg}.exr", ["P.X", "P.Y", "P.Z"])[0], -1)
eye = np.array(gspec.getattribute("dhdr:cameraPosition"), dtype=np.float64)
V = eye - P; V /= np.maximum(np.linalg.norm(V, axis=-1, keepdims=True), 1e-9)
NV, NL, LV = (N * V).sum(-1), (N * Ldir).sum(-1), (V * Ldir).sum(-1)
rough = chans(f"g_{cfg}.exr", ["roughness"])[0][0]
albedo = rgb(f"g_{cfg}.exr", "albedo.")

spec = rgb(f"d_{cfg}_spec.exr")
dh = {m: rgb(f"d_{cfg}_{m}.exr") - spec for m in ("burley", "lambert")}
cy_file = f"cy_{cfg}.exr"
cy = rgb(cy_file, "ViewLayer.DiffDir.") * rgb(cy_file, "ViewLayer.DiffCol.")
cyid = np.rint(chans(cy_file, ["ViewLayer.IndexOB.X"])[0][0]).astype(int)
E = float(sys.argv[4]) if len(sys.argv) > 4 else 3.0   # the sun's irradiance, W/m^2

# The Cycles 3.4 bsdf_principled_diffuse "full" formula written out (bsdf_principled_diffuse.h),
# times base colour, E cos(theta_l): what Cycles' DiffDir x DiffCol should hold per pixel.
FL, FV = (1 - np.clip(NL, 0, 1)) ** 5, (1 - np.clip(NV, 0, 1)) ** 5
RR = rough * (LV + 1)
fcy = (1 - 0.5 * FL) * (1 - 0.5 * FV) + RR * (FL + FV + FL * FV * (RR - 1))
model = albedo / np.pi * fcy * E * np.clip(NL, 0, None)

def erode(m):
    o = m.copy()
    o[1:] &= m[:-1]; o[:-1] &= m[1:]; o[:, 1:] &= m[:, :-1]; o[:, :-1] &= m[:, 1:]
    return o
names = ["", "sphere r=0", "sphere r=0.5", "sphere r=1", "floor r=1"]
print(f"[{cfg}] sun towards {np.round(Ldir, 3).tolist()}, E = {E} W/m^2; object masks dhdr vs Cycles IoU: " +
      ", ".join(f"{k}:{((obj == k) & (cyid == k)).sum() / max(((obj == k) | (cyid == k)).sum(), 1):.3f}" for k in range(1, 5)))
print(f"{'object':13s} {'pixels':7s} {'n':>5s} {'N.V':>5s} {'N.L':>5s} {'Cycles':>8s} {'burley/Cy':>9s} {'lambert/Cy':>10s}"
      f" {'p5-p95 burley/Cy':>17s} {'formula/Cy':>10s}")
rows = []
for k in range(1, 5):
    base = erode((obj == k) & (cyid == k)) & (NL > 0.1)
    lit = erode(base & (cy > 1e-4) & (dh["burley"] > 1e-4))     # away from shadow edges too
    for sel, m in (("all lit", lit), ("grazing", lit & (NV < 0.3)), ("facing", lit & (NV > 0.8))):
        n = int(m.sum())
        if n < 5:
            print(f"{names[k]:13s} {sel:7s} {n:5d}   (too few pixels)"); continue
        c = cy[m].mean()
        rb, rl, rf = dh["burley"][m].mean() / c, dh["lambert"][m].mean() / c, model[m].mean() / c
        q = np.percentile(dh["burley"][m] / cy[m], [5, 95])
        print(f"{names[k]:13s} {sel:7s} {n:5d} {NV[m].mean():5.2f} {NL[m].mean():5.2f} {c:8.4f} {rb:9.4f} {rl:10.4f}"
              f"   {q[0]:6.3f}-{q[1]:6.3f}  {rf:10.4f}")
        rows.append((cfg, names[k], sel, n, rb, rl, rf))
