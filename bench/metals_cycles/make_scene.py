#!/usr/bin/python3
"""make_scene.py OUT.gltf R,G,B METALLIC -- five spheres in a row (x = -1.4 ... 1.4, radius 0.3,
centre y = 0), roughness 0, 0.25, 0.5, 0.75, 1, the given base colour and metallic; no floor.
Fine tessellation (96 rings x 192 segments, vertex normals) so interpolated normals match the
true sphere. Node order = dhdr's id.object 1..5 = Cycles' IndexOB (cycles_render.py)."""
import base64, json, math, struct, sys
COL = [float(v) for v in sys.argv[2].split(",")]
MET = float(sys.argv[3])
R = 0.3
SPHERES = [(-1.4, "r0", 0.0), (-0.7, "r025", 0.25), (0.0, "r05", 0.5), (0.7, "r075", 0.75), (1.4, "r1", 1.0)]

def uv_sphere(cx, cy, cz, r, rings=96, segments=192):
    P, N, I = [], [], []
    for i in range(rings + 1):
        t = math.pi * i / rings
        for j in range(segments + 1):
            p = 2 * math.pi * j / segments
            n = (math.sin(t) * math.cos(p), math.cos(t), math.sin(t) * math.sin(p))
            N.append(n); P.append((cx + r * n[0], cy + r * n[1], cz + r * n[2]))
    for i in range(rings):
        for j in range(segments):
            a = i * (segments + 1) + j; b = a + segments + 1
            I += [a, a + 1, b, a + 1, b + 1, b]
    return P, N, I

blob = bytearray(); views, acc, meshes, nodes, mats = [], [], [], [], []
def view(data, target):
    while len(blob) % 4: blob.append(0)
    views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
    blob.extend(data); return len(views) - 1
def add(name, P, N, I, mat):
    pv = view(b"".join(struct.pack("<3f", *p) for p in P), 34962)
    nv = view(b"".join(struct.pack("<3f", *n) for n in N), 34962)
    iv = view(struct.pack("<%dI" % len(I), *I), 34963)
    acc.extend([{"bufferView": pv, "componentType": 5126, "count": len(P), "type": "VEC3",
                 "min": [min(p[k] for p in P) for k in range(3)], "max": [max(p[k] for p in P) for k in range(3)]},
                {"bufferView": nv, "componentType": 5126, "count": len(N), "type": "VEC3"},
                {"bufferView": iv, "componentType": 5125, "count": len(I), "type": "SCALAR"}])
    a = len(acc)
    meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": a - 3, "NORMAL": a - 2},
                                                  "indices": a - 1, "material": mat}]})
    nodes.append({"name": name, "mesh": len(meshes) - 1})
for x, name, rough in SPHERES:
    mats.append({"name": "mat_" + name, "pbrMetallicRoughness": {
        "baseColorFactor": COL + [1], "metallicFactor": MET, "roughnessFactor": rough}})
    add("sphere_" + name, *uv_sphere(x, 0.0, 0.0, R), len(mats) - 1)
g = {"asset": {"version": "2.0", "generator": "dhdr bench/metals_cycles/make_scene.py"},
     "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}], "nodes": nodes, "meshes": meshes,
     "materials": mats, "accessors": acc, "bufferViews": views,
     "buffers": [{"byteLength": len(blob),
                  "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}]}
json.dump(g, open(sys.argv[1], "w"))
