#!/usr/bin/python3
# analyze.py WORK_DIR [CYCLES_EXR]  (needs python3-openimageio, numpy; run.sh calls it)
import numpy as np, OpenImageIO as oiio, sys
D = sys.argv[1].rstrip("/") + "/"
def ch(path, name):
    b = oiio.ImageBuf(D + path); spec = b.spec()
    i = list(spec.channelnames).index(name)
    return b.get_pixels(oiio.FLOAT)[:, :, i].astype(np.float64)
gspec = oiio.ImageBuf(D + "g.exr").spec()
catcher_id = gspec.getattribute("dhdr:shadowCatcher")
_in = oiio.ImageInput.open(D + "g.exr"); _i = list(_in.spec().channelnames).index("id.object")
obj = _in.read_image(0, 0, _i, _i + 1, oiio.UINT32)[:, :, 0].astype(np.int64); _in.close()
ground = obj == catcher_id
sphere = (obj > 0) & (obj != catcher_id)
cy_name = sys.argv[2] if len(sys.argv) > 2 else "cycles_1024.exr"
cy = ch(cy_name, "ViewLayer.Combined.A")
cyidx = ch(cy_name, "ViewLayer.IndexOB.X")
cy_sphere = (cyidx >= 1) & (cyidx <= 3)

def dilate(m, r):
    out = np.zeros_like(m); H, W = m.shape
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            if dx * dx + dy * dy > r * r: continue
            s = np.zeros_like(m)
            s[max(dy,0):H+min(dy,0), max(dx,0):W+min(dx,0)] = m[max(-dy,0):H+min(-dy,0), max(-dx,0):W+min(-dx,0)]
            out |= s
    return out
iou = lambda a, b: (a & b).sum() / max((a | b).sum(), 1)
print(f"camera check: sphere-mask IoU dhdr id.object vs Cycles IndexOB = {iou(sphere, cy_sphere):.4f}"
      f" ({sphere.sum()} vs {cy_sphere.sum()} px)")
# measured region: dhdr ground pixels, minus a 2 px rim around either renderer's spheres (AA mix)
rim = dilate(sphere | cy_sphere, 2)
G = ground & ~rim
band = G & dilate(sphere, 20)
print(f"ground px {ground.sum()}, measured (rim-free) {G.sum()}, band(<=20px of a sphere) {band.sum()}")
rows = []
print(f"{'':10s} {'mean|d|':>8s} {'p95|d|':>8s} {'IoU>.1':>7s} {'IoU>.3':>7s} {'band mean':>9s} {'band mean d':>11s} {'all mean':>8s}")
for name in ["c0", "c16", "c256", "c256d"]:
    a = ch(name + ".exr", "A")
    d = np.abs(a - cy)[G]
    print(f"{name:10s} {d.mean():8.4f} {np.percentile(d,95):8.4f} {iou((a>0.1)&G,(cy>0.1)&G):7.3f} {iou((a>0.3)&G,(cy>0.3)&G):7.3f}"
          f" {a[band].mean():9.4f} {(a-cy)[band].mean():+11.4f} {a[G].mean():8.4f}")
print(f"{'cycles':10s} {'':8s} {'':8s} {'':7s} {'':7s} {cy[band].mean():9.4f} {'':11s} {cy[G].mean():8.4f}")
# Cycles noise estimate: 64-spp render vs 1024 (64 spp noise dominates; /4 -> 1024 spp)
try:
    c64 = ch("cy_m200_s64.exr", "ViewLayer.Combined.A")
    n = np.abs(c64 - cy)[G]
    print(f"Cycles noise: mean|cy64-cy1024| = {n.mean():.4f} -> est. mean abs noise at 1024 spp ~ {n.mean()/4:.4f}")
except Exception as e:
    print("no 64 spp render:", e)
# where the shadow is: split the band into the sun shadow (cycles>0.3) and the rest
for name in ["c0", "c16", "c256"]:
    a = ch(name + ".exr", "A")
    for lab, m in [("band&sunshadow(cy>.3)", band & (cy > 0.3)), ("band&cy<=.3", band & (cy <= 0.3)), ("far (>20px) ", G & ~band)]:
        print(f"  {name:5s} {lab:22s} n={m.sum():6d} dhdr {a[m].mean():.4f} cycles {cy[m].mean():.4f} diff {(a-cy)[m].mean():+.4f}")
