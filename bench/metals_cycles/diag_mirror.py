#!/usr/bin/python3
# diag_mirror.py WORK_DIR MATERIAL HDRI... -- the split-off sun on the mirror sphere (roughness 0): the sum over
# its pixels of dhdr's sun-only frame against what a mirror ball reflects of a sun of illuminance E: a ball of
# radius R seen from afar maps R^2/4 of image area to each steradian, so the sun covers E/L_sun * R^2/4 of it
# at radiance F0 L_sun: E F0 R^2 / 4 in radiance x area, / pixel area in pixel sums (F ~ F0: the glint faces the camera).
import numpy as np, OpenImageIO as oiio, math, sys
D, mat, hdris = sys.argv[1].rstrip("/") + "/", sys.argv[2], sys.argv[3:]
Y = np.array([.2126, .7152, .0722])
def rd(p, pre=""):
    b = oiio.ImageBuf(D + p); a = b.get_pixels(oiio.FLOAT); cn = list(b.spec().channelnames)
    return np.stack([a[..., cn.index(pre + c)] for c in "RGB"], -1)
inp = oiio.ImageInput.open(D + f"g_{mat}.exr"); i = list(inp.spec().channelnames).index("id.object")
obj = inp.read_image(0, 0, i, i + 1, oiio.UINT32)[:, :, 0]; inp.close()
F0 = rd(f"g_{mat}.exr", "albedo.")[obj == 1].mean(0)
pix = 2 * 6 * math.tan(math.radians(10.5 / 2)) / 120      # run.sh's camera: 6 m away, 10.5 deg over 120 rows
for h in hdris:
    E = oiio.ImageInput.open(D + h + ".ibl.exr").spec().getattribute("dhdr:sunIlluminance")
    if E is None: continue
    sun = rd(f"d_{mat}_{h}_sun.exr") @ Y; d = rd(f"d_{mat}_{h}_auto.exr") @ Y
    c = 0.5 * (rd(f"cy_{mat}_{h}_s1.exr", "ViewLayer.Combined.") + rd(f"cy_{mat}_{h}_s2.exr", "ViewLayer.Combined.")) @ Y
    m = obj == 1
    expect = (np.array(E) * F0) @ Y * 0.3 ** 2 / (4 * pix ** 2)
    print(f"{h:8s} {mat} r=0: the sun's glint summed over the sphere: dhdr {sun[m].sum():8.1f}, expected {expect:7.1f}"
          f" ({int((sun[m] > 0.01 * expect).sum())} pixel(s) hold it, brightest {sun[m].max():.1f});"
          f" whole sphere summed: dhdr {d[m].sum():8.1f}, Cycles {c[m].sum():8.1f}, difference {d[m].sum() - c[m].sum():+8.1f}")
