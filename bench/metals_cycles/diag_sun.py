#!/usr/bin/python3
# diag_sun.py WORK_DIR MATERIAL -- one directional light (angle 0, E = 1) instead of the HDRI, to take the
# BRDF apart: dhdr's frame against Cycles' Multiscatter GGX and single-scatter GGX renders, and both against
# the single-scattering GGX written out in numpy per pixel with (a) dhdr's form: height-correlated Smith,
# Schlick Fresnel; (b) Cycles 3.4's: separable Smith G1(v) G1(l), Fresnel interpolated by the dielectric
# Fresnel of IOR 1.5 (interpolate_fresnel_color). run.sh's diagnosis step renders the inputs.
import numpy as np, OpenImageIO as oiio, sys, json
D, mat = sys.argv[1].rstrip("/") + "/", sys.argv[2]
Lsun = -np.array(json.load(open(D + "pointsun.json"))["lights"][0]["direction"], float); Lsun /= np.linalg.norm(Lsun)
def chans(path, names, fmt=oiio.FLOAT):
    inp = oiio.ImageInput.open(D + path); cn = list(inp.spec().channelnames); spec = inp.spec()
    out = [inp.read_image(0, 0, cn.index(n), cn.index(n) + 1, fmt)[:, :, 0].astype(np.float64) for n in names]
    inp.close(); return out, spec
rgb = lambda p, pre="": np.stack(chans(p, [pre + c for c in "RGB"])[0], -1)
g = f"g_{mat}.exr"
(obj,), gs = chans(g, ["id.object"], oiio.UINT32)
N = np.stack(chans(g, ["N.X", "N.Y", "N.Z"])[0], -1); N /= np.linalg.norm(N, axis=-1, keepdims=True) + 1e-12
P = np.stack(chans(g, ["P.X", "P.Y", "P.Z"])[0], -1)
V = np.array(gs.getattribute("dhdr:cameraPosition")) - P; V /= np.linalg.norm(V, axis=-1, keepdims=True) + 1e-12
F0 = rgb(g, "albedo.")
rough = chans(g, ["roughness"])[0][0]
H = Lsun + V; H /= np.linalg.norm(H, axis=-1, keepdims=True)
NV, NL, NH, VH = (N * V).sum(-1), (N * Lsun).sum(-1), (N * H).sum(-1), (V * H).sum(-1)
a2 = np.maximum(rough ** 2, 1e-4) ** 2
Dg = a2 / (np.pi * (NH ** 2 * (a2 - 1) + 1) ** 2)
lam = lambda mu: 0.5 * (-1 + np.sqrt(1 + a2 * (1 - mu ** 2) / np.maximum(mu ** 2, 1e-12)))
Gc, Gs = 1 / (1 + lam(NV) + lam(NL)), 1 / ((1 + lam(NV)) * (1 + lam(NL)))
c = np.clip(VH, 0, 1)[..., None]
Fs = F0 + (1 - F0) * (1 - c) ** 5
def fdiel(cosi, eta=1.5):
    gg = np.sqrt(eta * eta - 1 + cosi * cosi); A = (gg - cosi) / (gg + cosi); B = (cosi * (gg + cosi) - 1) / (cosi * (gg - cosi) + 1)
    return 0.5 * A * A * (1 + B * B)
FH = (fdiel(c) - 0.04) / 0.96
Fc = F0 * (1 - FH) + FH
common = (Dg / (4 * np.maximum(NV, 1e-6)))[..., None]          # f NL E with E = 1: F D G / (4 NV)
ok = (NL > 0.05) & (NV > 0.05)
single_dhdr, single_cy = Fs * Gc[..., None] * common, Fc * Gs[..., None] * common
dh = rgb(f"d_{mat}_pointsun.exr")
cym, cys = rgb(f"cysun_{mat}_MULTI_GGX.exr", "ViewLayer.Combined."), rgb(f"cysun_{mat}_GGX.exr", "ViewLayer.Combined.")
cyid = np.rint(chans(f"cysun_{mat}_GGX.exr", ["ViewLayer.IndexOB.X"])[0][0]).astype(int)
Y = np.array([0.2126, 0.7152, 0.0722])
def erode(m):
    o = m.copy(); o[1:] &= m[:-1]; o[:-1] &= m[1:]; o[:, 1:] &= m[:, :-1]; o[:, :-1] &= m[:, 1:]; return o
print(f"\n[{mat}, one sun towards {np.round(Lsun, 3).tolist()}] luminance ratios of means over lit pixels (N.L, N.V > 0.05)")
print(f"{'sphere':7s} {'pixels':7s} {'n':>5s} {'dhdr/CyMulti':>12s} {'CyGGX/numpyCy':>13s} {'CyGGX/numpyDhdr':>15s}"
      f" {'dhdrMS/CyMS':>11s} {'CyMS/CyGGX':>10s} {'dhdrMS/single':>13s}  dhdr/CyMulti R G B")
for k in range(2, 6):
    base = erode((obj == k) & (cyid == k)) & ok
    for sel, m in (("all lit", base), ("grazing", base & (NV < 0.3)), ("facing", base & (NV > 0.8))):
        if m.sum() < 5: continue
        mean = lambda x: (x[m] @ Y).mean()
        msd, msc = mean(dh) - mean(single_dhdr), mean(cym) - mean(cys)
        ch = dh[m].mean(0) / cym[m].mean(0)
        print(f"r={[0, 0.25, 0.5, 0.75, 1][k-1]:<5} {sel:7s} {int(m.sum()):5d} {mean(dh) / mean(cym):12.3f} {mean(cys) / mean(single_cy):13.3f}"
              f" {mean(cys) / mean(single_dhdr):15.3f} {msd / msc if abs(msc) > 1e-9 else float('nan'):11.3f} {msc / mean(cys):10.3f}"
              f" {msd / mean(single_dhdr):13.3f}  {ch[0]:.3f} {ch[1]:.3f} {ch[2]:.3f}")
