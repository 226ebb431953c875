#!/usr/bin/python3
# modes.py WORK_DIR MATERIAL HDRI OUT.png -- rows: dhdr --env-specular split-sum, quadrature (= auto from
# roughness 0.3 up), Cycles; the same exposure (Cycles' 99th percentile = 1), gamma 2.2, 2x nearest.
import numpy as np, OpenImageIO as oiio, sys
D, mat, h, out = sys.argv[1].rstrip("/") + "/", sys.argv[2], sys.argv[3], sys.argv[4]
def rd(p, pre=""):
    b = oiio.ImageBuf(D + p); a = b.get_pixels(oiio.FLOAT); cn = list(b.spec().channelnames)
    return np.stack([a[..., cn.index(pre + c)] for c in "RGB"], -1)
cy = 0.5 * (rd(f"cy_{mat}_{h}_s1.exr", "ViewLayer.Combined.") + rd(f"cy_{mat}_{h}_s2.exr", "ViewLayer.Combined."))
ref = np.percentile(cy @ np.array([.2126, .7152, .0722]), 99)
tm = lambda x: np.clip(x / ref, 0, 1) ** (1 / 2.2)
img = np.concatenate([tm(rd(f"d_{mat}_{h}_split-sum.exr")), tm(rd(f"d_{mat}_{h}_quadrature.exr")), tm(cy)], 0)
img = img.repeat(2, 0).repeat(2, 1).astype(np.float32)
buf = oiio.ImageBuf(oiio.ImageSpec(img.shape[1], img.shape[0], 3, oiio.FLOAT))
buf.set_pixels(oiio.ROI(0, img.shape[1], 0, img.shape[0]), img)
buf.write(out, "uint8")
