#!/usr/bin/env python3
"""The project's own hostile corpus (issue 21): a seeded generator of damaged inputs for every
format the tools read, run through the tools as a user would.

Seeds are made by the tools themselves (a small G-buffer, a deep one, a lit frame, a baked IBL,
a probe volume, a lights file, a channel map, a glTF file, a pipeline file); each case mutates
one of them (EXR header attributes set to extreme values, bytes of the pixels flipped, the file
cut short; JSON values replaced by wrong types, extreme numbers, deleted or unknown keys; glTF
buffers damaged) and runs the tool that reads it. Every case must end in

  - exit 0 with every output present, readable and finite (a G-buffer's Z may be +Inf on its
    background, as the contract says), or
  - exit 1 with a message naming the damaged file, or exit 2 (a usage error) with a message,
    and no output;

never a signal, never the time limit, never a temporary left behind. The same seed gives the
same cases on every machine.

  tests/hostile/run.py TOOLS_DIR SOURCE_DIR [--cases N] [--seed S] [--keep DIR]
"""

import argparse
import base64
import glob
import json
import os
import random
import re
import shutil
import struct
import subprocess
import sys
import tempfile

TIMEOUT = 60  # seconds a case may take: the slowest honest case here takes about 2


def run(cmd, cwd):
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, errors="replace",
                           timeout=TIMEOUT, env=dict(os.environ, OMP_NUM_THREADS="1"))
        return p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        return "timeout", ""


# --- EXR headers -------------------------------------------------------------------------

def exr_attributes(data):
    """(name, type, value offset, value size) of each attribute of the first header."""
    out, at = [], 8
    while at < len(data) and data[at] != 0:
        end = data.index(b"\0", at)
        name = data[at:end].decode("latin1")
        tend = data.index(b"\0", end + 1)
        typ = data[end + 1:tend].decode("latin1")
        size = struct.unpack_from("<i", data, tend + 1)[0]
        out.append((name, typ, tend + 5, size))
        at = tend + 5 + size
    return out, at + 1


EXTREME_INTS = [0, -1, 1, 2, 7, 65535, 65536, 1 << 20, 2**31 - 1, -(2**31)]
EXTREME_FLOATS = [0.0, -0.0, 1e-45, -1.0, 1e38, float("inf"), float("-inf"), float("nan")]


def mutate_exr(data, rng):
    data = bytearray(data)
    attrs, header_end = exr_attributes(data)
    kind = rng.choice(["attribute", "attribute", "attribute", "pixels", "truncate"])
    if kind == "truncate":
        return bytes(data[:rng.randrange(8, len(data))]), "cut at byte"
    if kind == "pixels":
        for _ in range(rng.randint(1, 16)):
            i = rng.randrange(header_end, len(data))
            data[i] = rng.randrange(256)
        return bytes(data), "pixel bytes flipped"
    name, typ, at, size = rng.choice(attrs)
    if typ in ("box2i", "v2i", "v3i", "int") and size >= 4:
        for k in range(size // 4):
            if rng.random() < 0.6:
                struct.pack_into("<i", data, at + 4 * k, rng.choice(EXTREME_INTS))
    elif typ in ("float", "v2f", "v3f", "m44f", "box2f") or name.startswith("dhdr:"):
        for k in range(size // 4):
            if rng.random() < 0.5:
                struct.pack_into("<f", data, at + 4 * k, rng.choice(EXTREME_FLOATS))
    elif typ == "chlist":
        # A channel's name, type or sampling.
        i = at + rng.randrange(max(1, size))
        data[i] = rng.choice([0, 1, 2, 3, 0xFF, ord("X"), ord(".")])
    else:
        for _ in range(rng.randint(1, 4)):
            data[at + rng.randrange(max(1, size))] = rng.randrange(256)
    return bytes(data), f"header {name} ({typ})"


# --- JSON ----------------------------------------------------------------------------------

WRONG_VALUES = [None, True, -1, 0, 1e39, -1e39, 1e-320, 2**63, "", "x" * 300, [], {}, [1, 2],
                {"x": 1}, "../../../etc/passwd", "NaN"]


def json_paths(v, path=()):
    yield path
    if isinstance(v, dict):
        for k, x in v.items():
            yield from json_paths(x, path + (k,))
    elif isinstance(v, list):
        for i, x in enumerate(v):
            yield from json_paths(x, path + (i,))


def mutate_json(doc, rng, keep_buffers=True):
    doc = json.loads(json.dumps(doc))
    paths = [p for p in json_paths(doc) if p and not (keep_buffers and "uri" in p)]
    for _ in range(rng.randint(1, 3)):
        if not paths:
            break
        path = rng.choice(paths)
        parent = doc
        for k in path[:-1]:
            parent = parent[k]
        key = path[-1]
        what = rng.choice(["replace", "replace", "delete", "unknown", "duplicate"])
        try:
            if what == "replace":
                parent[key] = rng.choice(WRONG_VALUES)
            elif what == "delete":
                del parent[key]
            elif what == "unknown" and isinstance(parent, dict):
                parent["colour" if rng.random() < 0.5 else "rnage"] = 1
            elif what == "duplicate" and isinstance(parent, list):
                parent.extend([parent[key]] * rng.choice([1, 1000]))
        except (KeyError, IndexError, TypeError):
            pass
        paths = [p for p in json_paths(doc) if p and not (keep_buffers and "uri" in p)]
    text = json.dumps(doc, allow_nan=True)
    if rng.random() < 0.1:
        text = text[:rng.randrange(1, len(text))]  # cut short
    return text


def mutate_gltf_buffer(doc, rng):
    doc = json.loads(json.dumps(doc))
    buf = doc["buffers"][0]
    head, b64 = buf["uri"].split(",", 1)
    raw = bytearray(base64.b64decode(b64))
    kind = rng.choice(["floats", "indices", "truncate"])
    if kind == "truncate":
        raw = raw[:rng.randrange(len(raw))]
    else:
        for _ in range(rng.randint(1, 8)):
            i = rng.randrange(0, len(raw) - 4, 4)
            if kind == "floats":
                struct.pack_into("<f", raw, i, rng.choice(EXTREME_FLOATS))
            else:
                struct.pack_into("<I", raw, i, rng.choice([0xFFFFFFFF, 0x7FFFFFFF, 65535, 1 << 20]))
    buf["uri"] = head + "," + base64.b64encode(bytes(raw)).decode()
    return json.dumps(doc, allow_nan=True), "buffer " + kind


# --- the cases -----------------------------------------------------------------------------

class Corpus:
    def __init__(self, tools, source, work):
        self.tools, self.source, self.work = tools, source, work
        self.seed = os.path.join(work, "seed")
        os.makedirs(self.seed)

    def tool(self, name):
        return os.path.join(self.tools, name)

    def make_seeds(self):
        t, s, src = self.tool, self.seed, self.source
        cornell = os.path.join(src, "testdata", "cornell_box.gltf")
        glass = os.path.join(src, "testdata", "cornell_glass.gltf")
        lights = os.path.join(src, "testdata", "cornell_box.lights.json")
        steps = [
            [t("dhdr-gbuffer"), cornell, "--size", "16x12", "--lights-out", "lights.json", "-o",
             "g.exr"],
            [t("dhdr-gbuffer"), glass, "--size", "16x12", "--deep", "-o", "dg.exr"],
            [t("dhdr-light"), "g.exr", "--lights", lights, "-o", "lit.exr"],
            ["oiiotool", "--pattern", "fill:top=4,3,2:bottom=0.2,0.3,0.1", "32x16", "3", "-d",
             "half", "-o", "env.exr"],
            [t("dhdr-ibl"), "env.exr", "--base-width", "16", "--samples", "16", "-o", "env.ibl.exr"],
            [t("dhdr-probes"), cornell, "--grid", "2,2,2", "--rays", "16", "--bounces", "1", "-o",
             "p.probes.exr"],
        ]
        for cmd in steps:
            subprocess.run(cmd, cwd=s, check=True, capture_output=True)
        shutil.copy(cornell, os.path.join(s, "scene.gltf"))
        with open(os.path.join(s, "map.json"), "w") as f:
            json.dump({"depth": {"channels": ["Z"]}, "position": {"channels": ["P.X", "P.Y", "P.Z"]},
                       "normal": {"channels": ["N.X", "N.Y", "N.Z"]},
                       "albedo": {"channels": ["albedo.R", "albedo.G", "albedo.B"], "value": 0.8},
                       "coverage": {"channels": ["A"]}, "backgroundDepth": 1e9}, f)
        with open(os.path.join(s, "farm.json"), "w") as f:
            json.dump({"name": "hostile", "stages": [
                {"tool": "dhdr-gbuffer", "inputs": ["scene.gltf"], "output": "g.####.exr",
                 "options": ["--size", "16x12"]},
                {"tool": "dhdr-light", "inputs": ["g.####.exr"], "output": "l.####.exr",
                 "options": ["--scene", "scene.gltf", "--gi", "direct"]},
                {"tool": "dhdr-tonemap", "inputs": ["l.####.exr"], "output": "t.####.png",
                 "adapt": True}]}, f)
        self.lights = lights
        self.cornell = cornell

    def read(self, name, mode="rb"):
        with open(os.path.join(self.seed, name), mode) as f:
            return f.read()

    def case(self, rng, index):
        """(family, what, files {name: bytes}, command, outputs, damaged) of case `index`."""
        d = os.path.join(self.work, f"case{index:04d}")
        os.makedirs(d)
        family = rng.choice(["gbuffer", "deep", "lit", "ibl", "probes", "lights", "channels",
                             "gltf", "gltf-buffer", "farm"])
        t = self.tool
        files, what = {}, ""
        if family in ("gbuffer", "deep", "lit", "ibl", "probes"):
            seed = {"gbuffer": "g.exr", "deep": "dg.exr", "lit": "lit.exr", "ibl": "env.ibl.exr",
                    "probes": "p.probes.exr"}[family]
            data, what = mutate_exr(self.read(seed), rng)
            files["bad.exr"] = data
        if family == "gbuffer":
            # --gi direct: the G-buffer's reading is what is tried, not a probe bake per case.
            cmd = [t("dhdr-light"), "bad.exr", "--scene", self.cornell, "--gi", "direct", "--ao",
                   rng.choice(["off", "rt", "ssao"]), "-o", "out.exr"]
            if rng.random() < 0.5:
                cmd = [t("dhdr-aa"), os.path.join(self.seed, "lit.exr"), "--gbuffer", "bad.exr",
                       "-o", "out.exr"]
            outputs = ["out.exr"]
        elif family == "deep":
            cmd = [t("dhdr-light"), "bad.exr", "--lights", self.lights, "--deep-out", "deep.exr",
                   "-o", "out.exr"]
            outputs = ["out.exr", "deep.exr"]
        elif family == "lit":
            choice = rng.choice(["dhdr-bloom", "dhdr-tonemap", "dhdr-aa"])
            cmd = [t(choice), "bad.exr"]
            if choice == "dhdr-aa":
                cmd += ["--gbuffer", os.path.join(self.seed, "g.exr")]
            out = "out.png" if choice == "dhdr-tonemap" and rng.random() < 0.5 else "out.exr"
            cmd += ["-o", out]
            outputs = [out]
        elif family == "ibl":
            files["env.json"] = json.dumps(
                {"lights": [{"type": "environment", "image": "bad.exr"}]}).encode()
            cmd = [t("dhdr-light"), os.path.join(self.seed, "g.exr"), "--lights", "env.json",
                   "-o", "out.exr"]
            outputs = ["out.exr"]
        elif family == "probes":
            cmd = [t("dhdr-light"), os.path.join(self.seed, "g.exr"), "--scene", self.cornell,
                   "--probes", "bad.exr", "-o", "out.exr"]
            outputs = ["out.exr"]
        elif family == "lights":
            doc = json.loads(self.read("lights.json", "r"))
            files["bad.json"] = mutate_json(doc, rng).encode()
            what = "lights"
            cmd = [t("dhdr-light"), os.path.join(self.seed, "g.exr"), "--lights", "bad.json",
                   "-o", "out.exr"]
            outputs = ["out.exr"]
        elif family == "channels":
            doc = json.loads(self.read("map.json", "r"))
            files["bad.json"] = mutate_json(doc, rng).encode()
            what = "channel map"
            cmd = [t("dhdr-light"), os.path.join(self.seed, "g.exr"), "--channels", "bad.json",
                   "--camera-from", self.cornell, "--lights", self.lights, "-o", "out.exr"]
            outputs = ["out.exr"]
        elif family == "gltf":
            doc = json.loads(self.read("scene.gltf", "r"))
            files["bad.gltf"] = mutate_json(doc, rng).encode()
            what = "glTF JSON"
            cmd = [t("dhdr-gbuffer"), "bad.gltf", "--size", "16x12", "-o", "out.exr"]
            outputs = ["out.exr"]
        elif family == "gltf-buffer":
            doc = json.loads(self.read("scene.gltf", "r"))
            text, what = mutate_gltf_buffer(doc, rng)
            files["bad.gltf"] = text.encode()
            cmd = [t("dhdr-gbuffer"), "bad.gltf", "--size", "16x12", "-o", "out.exr"]
            outputs = ["out.exr"]
        else:  # farm
            doc = json.loads(self.read("farm.json", "r"))
            files["bad.json"] = mutate_json(doc, rng, keep_buffers=False).encode()
            shutil.copy(os.path.join(self.seed, "scene.gltf"), d)
            what = "pipeline"
            cmd = [t("dhdr-farm"), "plan", "bad.json", "--frames", "1-2"]
            outputs = []
        for name, data in files.items():
            with open(os.path.join(d, name), "wb") as f:
                f.write(data)
        damaged = [n for n in files if n.startswith("bad")]
        return family, what, cmd, outputs, damaged, d


def finite(path, gbuffer):
    """Whether oiiotool reads `path` and finds no NaN or Inf (a G-buffer's Z may be +Inf)."""
    # One oiiotool for the channel names and the counts (it was two, each paying OpenImageIO's
    # start-up).
    p = subprocess.run(["oiiotool", "--info", "-v", "--stats", path], capture_output=True,
                       text=True, errors="replace")
    if p.returncode != 0:
        return False, "unreadable: " + p.stderr.strip()[:200]
    names = []
    m = re.search(r"channel list: (.*)", p.stdout)
    if m:
        names = [c.strip().split(" ")[0] for c in m.group(1).split(",")]
    for label in ("NanCount", "InfCount"):
        m = re.search(label + r": ([0-9 ]+)", p.stdout)
        if not m:
            continue
        counts = [int(c) for c in m.group(1).split()]
        for i, c in enumerate(counts):
            if c and not (gbuffer and label == "InfCount" and i < len(names) and names[i] == "Z"):
                return False, f"{c} {label} in channel {names[i] if i < len(names) else i}"
    return True, ""


def check(case, rc, err):
    family, what, cmd, outputs, damaged, d = case
    left = [f for f in os.listdir(d) if ".tmp" in f]
    if rc == "timeout":
        return "did not finish within %d s" % TIMEOUT
    if rc < 0:
        return "killed by signal %d" % -rc
    if left:
        return "left temporaries " + ", ".join(left)
    if rc == 0:
        for o in outputs:
            if not os.path.exists(os.path.join(d, o)):
                return "exit 0 without " + o
            if o.endswith(".exr"):
                ok, why = finite(os.path.join(d, o), cmd[0].endswith("dhdr-gbuffer"))
                if not ok:
                    return f"exit 0, {o} {why}"
        return None
    if rc not in (1, 2):
        return f"exit {rc}"
    if not err.strip():
        return f"exit {rc} without a message"
    if "Traceback" in err:
        return f"exit {rc} with a Python traceback"
    if rc == 1 and damaged and not any(n in err for n in damaged):
        return "exit 1 without naming " + " or ".join(damaged) + ": " + err.strip()[:300]
    for o in outputs:
        if os.path.exists(os.path.join(d, o)):
            return f"exit {rc} but {o} was written"
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tools")
    ap.add_argument("source")
    ap.add_argument("--cases", type=int, default=160)
    ap.add_argument("--seed", type=int, default=21)
    ap.add_argument("--keep", help="keep the cases in this folder")
    args = ap.parse_args()
    work = args.keep or tempfile.mkdtemp(prefix="dhdr_hostile_")
    if args.keep:
        shutil.rmtree(work, ignore_errors=True)
        os.makedirs(work)
    corpus = Corpus(os.path.abspath(args.tools), os.path.abspath(args.source), work)
    corpus.make_seeds()
    rng = random.Random(args.seed)
    passed = failed = 0
    outcomes = {}
    for i in range(args.cases):
        case = corpus.case(rng, i)
        rc, err = run(case[2], case[5])
        problem = check(case, rc, err)
        key = (case[0], "exit %s" % rc)
        outcomes[key] = outcomes.get(key, 0) + 1
        if problem:
            failed += 1
            print(f"FAIL case {i} ({case[0]}: {case[1]}): {problem}\n  in {case[5]}: "
                  + " ".join(os.path.basename(c) if c.startswith(corpus.tools) else c
                             for c in case[2]))
        else:
            passed += 1
            if not args.keep:
                shutil.rmtree(case[5])
    for (family, exit_), n in sorted(outcomes.items()):
        print(f"  {family:12s} {exit_:8s} {n}")
    if not args.keep and failed == 0:
        shutil.rmtree(work)
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
