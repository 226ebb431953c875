"""What the farm tests share: the tools' folder, a small sequence whose brightness steps (so
that adaptation matters), its pipeline file, and the same chain run by the tools directly."""

import json
import os
import subprocess

SOURCE = os.environ.get("DHDR_SOURCE", os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.abspath(os.environ.get("DHDR_BIN", os.path.join(SOURCE, "build", "apps")))
SCENE = os.path.abspath(os.path.join(SOURCE, "testdata", "cornell_box.gltf"))
LIGHTS = os.path.abspath(os.path.join(SOURCE, "testdata", "cornell_box.lights.json"))
SIZE = "96x64"
FRAMES = range(1, 13)


def brightness(frame):
    """Dim for six frames, then eight times brighter: the adapted exposure lags behind."""
    return 0.4 if frame <= 6 else 3.2


def write_lights(folder, stem="lights", broken=None):
    """lights.0001.json ... with every light scaled by brightness(frame); frame `broken`
    gets a file that is not JSON."""
    with open(LIGHTS, encoding="utf-8") as f:
        base = json.load(f)
    for frame in FRAMES:
        path = os.path.join(folder, "%s.%04d.json" % (stem, frame))
        with open(path, "w", encoding="utf-8") as f:
            if frame == broken:
                f.write("{ this is not a lights file")
                continue
            doc = json.loads(json.dumps(base))
            for light in doc["lights"]:
                light["intensity"] = light["intensity"] * brightness(frame)
            json.dump(doc, f)


def pipeline(out, lights="lights"):
    """The pipeline file's content: gbuffer -> light -> bloom -> tonemap with adaptation."""
    return {
        "name": os.path.basename(out),
        "stages": [
            {"tool": "dhdr-gbuffer", "inputs": [SCENE], "output": out + "/gbuf.####.exr",
             "options": ["--size", SIZE]},
            {"tool": "dhdr-light", "inputs": [out + "/gbuf.####.exr"],
             "output": out + "/hdr.####.exr", "options": ["--lights", lights + ".####.json"]},
            {"tool": "dhdr-bloom", "inputs": [out + "/hdr.####.exr"],
             "output": out + "/bloom.####.exr"},
            {"tool": "dhdr-tonemap", "name": "tonemap", "inputs": [out + "/bloom.####.exr"],
             "output": out + "/frame.####.png", "adapt": True, "fps": 24},
        ],
    }


def write_pipeline(folder, name, lights="lights"):
    path = os.path.join(folder, name + ".farm.json")
    with open(path, "w", encoding="utf-8") as f:
        json.dump(pipeline(name, lights), f, indent=2)
    return path


def tool(name, *args, cwd):
    out = subprocess.run([os.path.join(BIN, name)] + list(args), cwd=cwd, capture_output=True,
                         text=True)
    if out.returncode != 0:
        raise AssertionError("%s %s failed (%d): %s" % (name, " ".join(args), out.returncode,
                                                        out.stderr))


def reference(folder):
    """The chain over frames 1-12, each stage one process, adaptation in one --adapt run."""
    os.makedirs(os.path.join(folder, "ref"), exist_ok=True)
    frames = "%d-%d" % (FRAMES[0], FRAMES[-1])
    tool("dhdr-gbuffer", SCENE, "-o", "ref/gbuf.####.exr", "--size", SIZE, "--frames", frames,
         cwd=folder)
    tool("dhdr-light", "ref/gbuf.####.exr", "--lights", "lights.####.json", "-o",
         "ref/hdr.####.exr", "--frames", frames, cwd=folder)
    tool("dhdr-bloom", "ref/hdr.####.exr", "-o", "ref/bloom.####.exr", "--frames", frames,
         cwd=folder)
    tool("dhdr-tonemap", "ref/bloom.####.exr", "--adapt", "--fps", "24", "-o",
         "ref/frame.####.png", "--frames", frames, "--stats-out", "ref/stats.json", cwd=folder)


def same_pixels(a, b):
    """OpenImageIO's idiff: exit 0 when every pixel is equal (-fail 0 -warn 0)."""
    out = subprocess.run(["idiff", "-q", "-fail", "0", "-warn", "0", a, b],
                         capture_output=True, text=True)
    return out.returncode == 0


def farm(*args, cwd, env=None):
    return subprocess.run([os.path.join(BIN, "dhdr-farm")] + list(args), cwd=cwd, env=env,
                          capture_output=True, text=True)
