#!/usr/bin/python3
# summary.py WORK_DIR -- the markdown tables of README.md from analyze.py's rows_*.json
import json, glob, sys
D = sys.argv[1].rstrip("/") + "/"
rows = [r for f in sorted(glob.glob(D + "rows_*.json")) for r in json.load(open(f))]
get = lambda m, h, s, mode: next((r for r in rows if (r["mat"], r["hdri"], r["sphere"], r["mode"]) == (m, h, s, mode)), None)
mats = [m for m in ("copper", "neutral", "white") if any(r["mat"] == m for r in rows)]
hdris = [h for h in ("forest", "sunrise", "sky", "furnace") if any(r["hdri"] == h for r in rows)]
spheres = ["r=0", "r=0.25", "r=0.5", "r=0.75", "r=1"]
modes = ["split-sum", "quadrature", "auto"]
for m in mats:
    print(f"\n**{m}**: mean(dhdr)/mean(Cycles) of the luminance; p95 of the per-pixel |dhdr/Cycles − 1| in brackets; "
          f"Cycles' own p95 (two seeds); auto's R/G/B ratios\n")
    print("| HDRI | sphere | split-sum | quadrature | auto (default) | Cycles noise p95 | auto R / G / B | auto grazing / facing | split-sum grazing |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for h in hdris:
        for s in spheres:
            r = {md: get(m, h, s, md) for md in modes}
            if r["auto"] is None: continue
            cells = " | ".join(f"{r[md]['ratio']:.3f} ({r[md]['p95']:.2f})" for md in modes)
            print(f"| {h} | {s} | {cells} | {r['auto']['noise95']:.2f} | "
                  + " / ".join(f"{v:.3f}" for v in r["auto"]["rgb"])
                  + f" | {r['auto']['graz']:.3f} / {r['auto']['face']:.3f} | {r['split-sum']['graz']:.3f} |")
