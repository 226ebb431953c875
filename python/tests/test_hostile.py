"""What crashed the module (issue 48): lights that hold themselves or nest without end, G-buffer
normals without a direction, and Ctrl-C during long calls. The calls that crashed run in a
child interpreter, so that a crash fails its test rather than the whole run."""
import os
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import dhdr
from conftest import LIGHTS, TESTDATA

CORNELL = str(TESTDATA / "cornell_box.gltf")
MODULE_DIR = str(pathlib.Path(dhdr.__file__).resolve().parent.parent)


def child(code):
    """Starts CODE in another interpreter that imports this build's dhdr; CODE prints 'ready'
    (and flushes) when the call to interrupt is about to start."""
    env = dict(os.environ, PYTHONPATH=MODULE_DIR)
    return subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)


def interrupted(code, delay=1.0, timeout=60):
    """Runs CODE, sends it SIGINT `delay` seconds after it is ready, and returns (exit status,
    stdout, stderr); a child still running after `timeout` seconds is killed (status None)."""
    p = child(code)
    assert p.stdout.readline().strip() == "ready", p.stderr.read()
    time.sleep(delay)
    p.send_signal(signal.SIGINT)
    try:
        out, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        p.kill()
        out, err = p.communicate()
        return None, out, err
    return p.returncode, out, err


def test_lights_that_hold_themselves_or_nest_without_end_are_value_errors(gbuffer):
    # A list holding itself, or lists nested 100000 deep, recursed until the stack overflowed.
    code = f"""
import dhdr
itself = []
itself.append(itself)
light = {{"type": "point", "position": [0, 0.5, 0], "intensity": 1.0}}
looped = dict(light)
looped["next"] = looped
deep_list, deep_dict = light, light
for _ in range(100000):
    deep_list, deep_dict = [deep_list], {{"lights": deep_dict}}
g = dhdr.read_gbuffer({str(gbuffer)!r})
for given in [itself, [light, itself], looped, deep_list, deep_dict]:
    for call in [lambda: dhdr.read_lights(given), lambda: dhdr.light(g, given)]:
        try:
            call()
            print("accepted")
        except ValueError as e:
            print(e)
# What a lights document holds still reads.
print(len(dhdr.read_lights([[light], {{"lights": [light, light]}}])))
"""
    p = child(code)
    out, err = p.communicate(timeout=120)
    assert p.returncode == 0, err
    itself = "lights: a list or dict that holds itself"
    deep = "lights: nested more than 32 lists or dicts deep"
    assert out.splitlines() == [itself] * 6 + [deep] * 4 + ["3"], err


def test_normals_without_a_direction_are_lit_finite(gbuffer):
    # NaN, ±Inf or zero in every component of N indexed the multiple-scattering table with a
    # NaN cosine (SIGSEGV).
    code = f"""
import numpy as np, dhdr
g = dhdr.read_gbuffer({str(gbuffer)!r})
p = g.pixels.copy()
n = g.channels.index("N.X")
covered = np.argwhere(p[..., g.channels.index("A")] > 0)
for (y, x), v in zip(covered[::97][:4], [np.nan, np.inf, -np.inf, 0.0]):
    p[y, x, n:n + 3] = v
bad = dhdr.Image(p, g.channels)
for name, value in g.attributes.items():
    bad.set_attribute(name, value)
out = dhdr.light(bad, {str(LIGHTS)!r}).pixels
print("finite" if np.isfinite(out).all() else "not finite")
"""
    p = child(code)
    out, err = p.communicate(timeout=120)
    assert p.returncode == 0, err
    assert out.strip() == "finite", err


def test_a_wide_sun_over_an_animated_scene_does_not_hang():
    # Issue 48: light(g, sun of angle 90 or 179 degrees, scene=animated) never returned on two
    # threads (Embree's coherent packets through instances). A call takes a fraction of a
    # second; several calls in a child that is killed if it has not finished in 120 s.
    animated = str(TESTDATA / "cornell_animated.gltf")
    code = f"""
import dhdr
scene = dhdr.Scene({animated!r})
g = dhdr.render_gbuffer(scene, size=(64, 64), frame=12)
for angle in (90, 179):
    sun = [{{"type": "directional", "direction": [0.3, -1, -0.2], "intensity": 3,
             "angle": angle}}]
    for _ in range(4):
        dhdr.light(g, sun, scene=scene, nthreads=2)
print("lit")
"""
    p = child(code)
    try:
        out, err = p.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        p.kill()
        p.communicate()
        pytest.fail("light() with a wide sun over an animated scene did not return in 120 s")
    assert p.returncode == 0, err
    assert out.strip() == "lit", err


def test_ctrl_c_stops_render_gbuffer(tmp_path):
    # A deep frame of 16000 x 16000 under a 3 GiB address space: the render runs for minutes and
    # would run out of memory before it ends (it raised MemoryError from std::bad_alloc, or the
    # interpreter died); Ctrl-C must stop it at once with KeyboardInterrupt and a clean exit.
    code = f"""
import resource, dhdr
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
scene = dhdr.Scene({CORNELL!r})
print("ready", flush=True)
try:
    dhdr.render_gbuffer(scene, size=(16000, 16000), deep=True)
    print("finished")
except KeyboardInterrupt:
    print("KeyboardInterrupt")
"""
    status, out, err = interrupted(code)
    assert status == 0, err
    assert out.strip() == "KeyboardInterrupt", err


def test_ctrl_c_stops_bake_probes_and_writes_nothing(tmp_path):
    # 1024 probes of 4096 rays with 256 shadow samples: over a minute uninterrupted.
    out_file = tmp_path / "probes.exr"
    code = f"""
import dhdr
scene = dhdr.Scene({CORNELL!r})
print("ready", flush=True)
try:
    dhdr.bake_probes(scene, {str(out_file)!r}, {str(LIGHTS)!r}, max_probes=1024, rays=4096,
                     shadow_samples=256, bounces=2)
    print("finished")
except KeyboardInterrupt:
    print("KeyboardInterrupt")
"""
    status, out, err = interrupted(code, timeout=40)
    assert status == 0, err
    assert out.strip() == "KeyboardInterrupt", err
    assert list(tmp_path.iterdir()) == []


def test_ctrl_c_stops_the_path_tracer_and_leaves_dst_as_it_was(gbuffer):
    # 64 x 48 pixels of 65536 paths: minutes uninterrupted; it ran on 12 s after SIGINT.
    code = f"""
import numpy as np, dhdr
scene = dhdr.Scene({CORNELL!r})
g = dhdr.read_gbuffer({str(gbuffer)!r})
dst = dhdr.Image(np.full((48, 64, 4), 7.0, np.float32))
print("ready", flush=True)
try:
    dhdr.light(dst, g, None, scene=scene, gi="path", spp=65536)
    print("finished")
except KeyboardInterrupt:
    print("KeyboardInterrupt", bool((dst.pixels == 7.0).all()))
"""
    start = time.monotonic()
    status, out, err = interrupted(code, timeout=30)
    assert status == 0, err
    assert out.strip() == "KeyboardInterrupt True", err
    assert time.monotonic() - start < 20


def test_ctrl_c_stops_bake_ibl_and_writes_nothing(tmp_path):
    out_file = tmp_path / "sky.exr"
    code = f"""
import numpy as np, dhdr
sky = np.random.default_rng(1).uniform(0.1, 2.0, (256, 512, 3)).astype(np.float32)
print("ready", flush=True)
try:
    dhdr.bake_ibl(sky, {str(out_file)!r}, base_width=4096, samples=65536, dfg_samples=65536)
    print("finished")
except KeyboardInterrupt:
    print("KeyboardInterrupt")
"""
    status, out, err = interrupted(code, timeout=30)
    assert status == 0, err
    assert out.strip() == "KeyboardInterrupt", err
    assert list(tmp_path.iterdir()) == []


def test_interrupted_calls_stop_within_a_second_and_leak_nothing(gbuffer):
    # Each call interrupted 0.2 s in; the resident memory after 40 such calls is what it was
    # after 10 (a cancelled pass whose buffers were never freed grew it by its output each time).
    code = f"""
import os, signal, threading, time, dhdr
scene = dhdr.Scene({CORNELL!r})
g = dhdr.read_gbuffer({str(gbuffer)!r})
def rss():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
late, sizes = 0.0, []
for i in range(40):
    timer = threading.Timer(0.2, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    start = time.monotonic()
    try:
        dhdr.light(g, scene=scene, gi="path", spp=4096)
    except KeyboardInterrupt:
        pass
    late = max(late, time.monotonic() - start - 0.2)
    sizes.append(rss())
print(late, sizes[9], sizes[-1])
"""
    p = child(code)
    out, err = p.communicate(timeout=120)
    assert p.returncode == 0, err
    late, after10, after40 = map(float, out.split())
    assert late < 1.0
    assert after40 - after10 < 8 << 20, (after10, after40)
