"""The example shot (docs/examples/shot.farm.json, testdata/shot.gltf) through dhdr-farm on a
real single-node Slurm cluster (slurm_cluster.py), six frames at 160x120 in two chunks, checked
against answers the test works out itself:

- each frame's G-buffer shows its own time: dhdr:animationTime = N / 24, its pixels those of
  dhdr-gbuffer --frame N run alone, and every visible point of the turning block, the hopping
  block and the skinned arm lies on that object posed at N / 24 by the test (rotations about
  the pivot, the Hermite hop, the skin's matrices), not at the frame before;
- the motion layer on what moves (and on what does not) is the reprojection the test computes
  from the neighbouring frames' cameras and its own poses;
- each frame's lights file has the sweeping spot where it points at N / 24;
- motion blur changed the frames; the final PNGs exist;
- eye adaptation runs on across the chunks: each adapted luminance follows from the one
  before by the seed's formula, and the PNGs are those of one dhdr-tonemap --adapt run.
"""

import base64
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest

import farm_fixture as fx
from slurm_cluster import SlurmCluster

# python3-numpy and python3-openimageio come with the build's dependencies
# (scripts/install-deps.sh): without them the test fails to import, it is not skipped.
import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.join(fx.SOURCE, "testdata"))
import make_shot as shot  # noqa: E402  (the arm's mesh and the animation's keys)

FPS = 24.0
FIRST, LAST, CHUNK = 8, 13, 3  # the spot comes on at frame 5; frames 10-13 brighten
SIZE = (160, 120)
GLTF = os.path.join(fx.SOURCE, "testdata", "shot.gltf")


def lerp_keys(keys, t):
    """A LINEAR channel of angles about one axis (slerp between rotations about one axis
    turns the angle linearly), held at its ends."""
    if t <= keys[0][0]:
        return keys[0][1]
    for (t0, a0), (t1, a1) in zip(keys, keys[1:]):
        if t <= t1:
            return a0 + (a1 - a0) * (t - t0) / (t1 - t0)
    return keys[-1][1]


def rotation(axis, degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    x, y, z = axis
    return np.array([[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
                     [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
                     [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]])


def affine(r=None, t=(0, 0, 0)):
    m = np.eye(4)
    if r is not None:
        m[:3, :3] = r
    m[:3, 3] = t
    return m


def hop(t):
    """The short block's CUBICSPLINE rise: Hermite with zero tangents, up at 0.5 s, down at 1."""
    half = 0.5 * shot.DURATION
    if t <= 0 or t >= 2 * half:
        return 0.0
    s = t / half if t <= half else (t - half) / half
    h = 3 * s * s - 2 * s ** 3
    return shot.HOP * (h if t <= half else 1 - h)


class Gltf:
    """The rest geometry of the shot's meshes, read from the file's own buffers."""

    def __init__(self, path):
        with open(path) as f:
            self.doc = json.load(f)
        self.buffers = [base64.b64decode(b["uri"].split(",", 1)[1]) for b in self.doc["buffers"]]

    def accessor(self, index):
        a = self.doc["accessors"][index]
        view = self.doc["bufferViews"][a["bufferView"]]
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[a["type"]]
        code = {5126: "f", 5123: "H", 5125: "I", 5121: "B"}[a["componentType"]]
        data = self.buffers[view["buffer"]]
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        values = struct.unpack_from("<%d%s" % (a["count"] * width, code), data, start)
        return np.array(values, dtype=np.float64).reshape(a["count"], width)

    def triangles(self, mesh_name):
        """(positions, triangle vertex indices) of a one-primitive mesh."""
        mesh = next(m for m in self.doc["meshes"] if m["name"] == mesh_name)
        p = mesh["primitives"][0]
        positions = self.accessor(p["attributes"]["POSITION"])
        if "indices" in p:
            tris = self.accessor(p["indices"]).astype(int).reshape(-1, 3)
        else:
            tris = np.arange(len(positions)).reshape(-1, 3)
        return positions, tris


def transform(m, points):
    return points @ m[:3, :3].T + m[:3, 3]


class Poses:
    """Each moving mesh's vertices at time t, worked out here from the keys."""

    def __init__(self, gltf):
        self.tall = gltf.triangles("tall_block")
        self.short = gltf.triangles("short_block")
        arm_positions, self.arm_tris = gltf.triangles("arm")
        _, _, joints, weights, _ = shot.arm_mesh()
        self.arm_rest = arm_positions
        self.joints = np.array(joints).reshape(-1, 4).astype(int)
        self.weights = np.array(weights).reshape(-1, 4)

    def tall_block(self, t):
        c = np.array(shot.TALL_CENTRE)
        m = affine(t=c) @ affine(rotation((0, 1, 0), lerp_keys(shot.TALL_TURN, t))) @ \
            affine(t=-c)
        return transform(m, self.tall[0]), self.tall[1]

    def short_block(self, t):
        return self.short[0] + np.array([0.0, hop(t), 0.0]), self.short[1]

    def arm(self, t):
        # Joint matrices world(joint) x inverseBind(joint); the bind pose is the rest pose
        # of the joints (the shoulder at the base, the elbow UPPER above it, no rotation).
        base = np.array(shot.ARM_BASE)
        up = np.array([0.0, shot.UPPER, 0.0])
        shoulder = affine(t=base) @ affine(rotation((0, 0, 1), lerp_keys(shot.SHOULDER_ROLL, t)))
        elbow = shoulder @ affine(t=up) @ affine(rotation((0, 0, 1),
                                                         lerp_keys(shot.ELBOW_ROLL, t)))
        skin = [shoulder @ affine(t=-base), elbow @ affine(t=-(base + up))]
        posed = np.zeros_like(self.arm_rest)
        for k in range(4):
            for j, m in enumerate(skin):
                w = self.weights[:, k] * (self.joints[:, k] == j)
                posed += w[:, None] * transform(m, self.arm_rest)
        return posed, self.arm_tris


def candidates(points, vertices, tris, tolerance=1e-4):
    """Which triangles each point lies on (within `tolerance` metres of the plane, inside
    with a little slack), the point's heights over their planes and its barycentric
    coordinates in each (points x triangles)."""
    a, b, c = vertices[tris[:, 0]], vertices[tris[:, 1]], vertices[tris[:, 2]]
    n = np.cross(b - a, c - a)
    area2 = np.linalg.norm(n, axis=1)
    unit = n / area2[:, None]
    d = points[:, None, :] - a[None, :, :]  # points x triangles x 3
    height = np.abs(np.einsum("ptk,tk->pt", d, unit))
    # P - a = u (b - a) + v (c - a), so u = ((P - a) x (c - a)).n / |n|^2 and
    # v = ((b - a) x (P - a)).n / |n|^2.
    w_b = np.einsum("ptk,tk->pt", np.cross(d, (c - a)[None]), unit) / area2
    w_c = np.einsum("ptk,tk->pt", np.cross(b - a, d), unit) / area2
    w_a = 1 - w_b - w_c
    slack = 1e-3
    inside = (height < tolerance) & (w_a > -slack) & (w_b > -slack) & (w_c > -slack)
    return inside, height, np.stack([w_a, w_b, w_c], axis=2)


def locate(points, vertices, tris):
    """For each point the triangle it lies on (-1 where none holds it): near an edge a point is
    within the tolerance of the next face too, so the nearest plane."""
    inside, height, _ = candidates(points, vertices, tris)
    return np.where(inside.any(axis=1), np.where(inside, height, np.inf).argmin(axis=1), -1)


class GBuffer:
    def __init__(self, path):
        inp = oiio.ImageInput.open(path)
        if inp is None:
            raise AssertionError("%s: %s" % (path, oiio.geterror()))
        self.spec = inp.spec()
        self.channels = list(self.spec.channelnames)
        self.pixels = inp.read_image(format="float")
        # Ids are uint: read as floats they would be normalised to [0, 1].
        k = self.channels.index("id.object")
        self.ids = inp.read_image(0, 0, k, k + 1, "uint")[:, :, 0]
        inp.close()

    def attribute(self, name):
        return self.spec.getattribute(name)

    def channel(self, name):
        return self.pixels[:, :, self.channels.index(name)]

    def object_mask(self, name):
        names = list(self.attribute("dhdr:objectNames"))
        return (self.ids == names.index(name)) & (self.channel("A") > 0)

    def positions(self, mask):
        return np.stack([self.channel("P." + c)[mask] for c in "XYZ"], axis=1).astype(np.float64)

    def raster(self, points):
        """Raster positions (pixels, y up) of world points through this frame's worldToNDC
        (OpenEXR's: Imath row vectors, NDC in [-1, 1], +Y up)."""
        m = np.array(self.attribute("worldToNDC"), dtype=np.float64).reshape(4, 4)
        h = np.hstack([points, np.ones((len(points), 1))]) @ m
        ndc = h[:, :2] / h[:, 3:4]
        return np.stack([(ndc[:, 0] + 1) / 2 * SIZE[0], (ndc[:, 1] + 1) / 2 * SIZE[1]], axis=1)


@unittest.skipUnless(os.geteuid() == 0, "starting munged and slurmd needs root")
class Shot(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="dhdr-shot-test-")
        os.chmod(cls.dir, 0o755)
        cls.pipeline = cls.write_pipeline()
        with SlurmCluster() as cluster:
            r = fx.farm("submit", cls.pipeline, "--frames", "%d-%d" % (FIRST, LAST), "--chunk",
                        str(CHUNK), "--wait", cwd=cls.dir, env=cluster.env)
        if r.returncode != 0:
            raise AssertionError("dhdr-farm on Slurm failed (%d):\n%s%s" % (
                r.returncode, r.stdout, r.stderr))
        cls.farm_output = r.stdout
        gltf = Gltf(GLTF)
        cls.poses = Poses(gltf)
        cls.gbuffers = {n: GBuffer(cls.path("out", "shot.gbuf.%04d.exr" % n))
                        for n in range(FIRST, LAST + 1)}

    @classmethod
    def tearDownClass(cls):
        if not os.environ.get("DHDR_KEEP_SLURM"):
            shutil.rmtree(cls.dir, ignore_errors=True)

    @classmethod
    def path(cls, *parts):
        return os.path.join(cls.dir, *parts)

    @classmethod
    def write_pipeline(cls):
        """The shipped example, its files found from here, its outputs in the test's folder,
        at 160x120. At this size a frame moves at most 3-4 pixels, and half a frame's shutter
        (the example's) blurs less than a pixel, which McGuire's filter rightly leaves as it
        was: the test opens the shutter to 2 frames so that the blur shows."""
        example = os.path.join(fx.SOURCE, "docs", "examples", "shot.farm.json")
        with open(example) as f:
            doc = json.load(f)

        def moved(text):
            if text.startswith("../../out/shot/"):
                return "out/" + text[len("../../out/shot/"):]
            if text.startswith("../../"):
                return os.path.join(fx.SOURCE, text[len("../../"):])
            return text

        for stage in doc["stages"]:
            stage["inputs"] = [moved(t) for t in stage["inputs"]]
            stage["output"] = moved(stage["output"])
            options = [moved(t) for t in stage.get("options", [])]
            if "--size" in options:
                options[options.index("--size") + 1] = "%dx%d" % SIZE
            if "--shutter" in options:
                options[options.index("--shutter") + 1] = "2"
            stage["options"] = options
        path = cls.path("shot.farm.json")
        with open(path, "w") as f:
            json.dump(doc, f, indent=2)
        return path

    def test_the_farm_ran_every_stage_on_slurm(self):
        self.assertEqual(self.farm_output.count("as Slurm job"), 8, self.farm_output)
        for n in range(FIRST, LAST + 1):
            for name in ("gbuf", "lights", "hdr", "aa", "mb", "bloom"):
                ext = "json" if name == "lights" else "exr"
                self.assertTrue(os.path.isfile(self.path("out", "shot.%s.%04d.%s" % (
                    name, n, ext))), "%s of frame %d" % (name, n))
            png = self.path("out", "shot.%04d.png" % n)
            self.assertTrue(os.path.isfile(png), png)
            spec = oiio.ImageInput.open(png).spec()
            self.assertEqual((spec.width, spec.height), SIZE)

    def test_each_frame_shows_its_own_time(self):
        for n, g in self.gbuffers.items():
            self.assertAlmostEqual(g.attribute("dhdr:animationTime"), n / FPS, places=6)
            self.assertEqual(g.attribute("dhdr:fps"), FPS)
            # The chunk's frame is the tool's frame N rendered alone.
            alone = self.path("alone.%04d.exr" % n)
            fx.tool("dhdr-gbuffer", GLTF, "--frame", str(n), "--size", "%dx%d" % SIZE,
                    "-o", alone, cwd=self.dir)
            self.assertTrue(fx.same_pixels(alone, self.path("out", "shot.gbuf.%04d.exr" % n)),
                            "frame %d differs from dhdr-gbuffer --frame %d" % (n, n))

    def test_what_moves_is_where_the_frame_time_puts_it(self):
        for name in ("tall_block", "short_block", "arm"):
            pose = getattr(self.poses, name)
            for n, g in self.gbuffers.items():
                mask = g.object_mask(name)
                if name == "short_block":
                    # It only rises: its sides stay in their planes, its top does not.
                    mask &= g.channel("N.Y") > 0.9
                points = g.positions(mask)
                self.assertGreater(len(points), 20, "%s hardly in view at frame %d" % (name, n))
                on = np.mean(locate(points, *pose(n / FPS)) >= 0)
                self.assertGreater(on, 0.99, "%s at frame %d: %.1f %% of its pixels on the "
                                   "pose of %g s" % (name, n, 100 * on, n / FPS))
                # Consecutive frames differ where things move: the pose of the frame before
                # does not hold these points. (Not for the arm: it bends about z, nearly the
                # camera's axis, so the face in view slides within its own plane; its motion
                # is checked in test_motion_is_the_reprojection_of_the_poses.)
                if name != "arm":
                    before = np.mean(locate(points, *pose((n - 1) / FPS)) >= 0)
                    self.assertLess(before, 0.5, "%s at frame %d is on the pose of frame %d "
                                    "too" % (name, n, n - 1))

    def test_motion_is_the_reprojection_of_the_poses(self):
        static = ("floor", "back_wall", "left_wall", "right_wall", "ceiling")
        for n in range(FIRST + 1, LAST):
            g, before, after = self.gbuffers[n], self.gbuffers[n - 1], self.gbuffers[n + 1]
            for name in static + ("tall_block", "short_block", "arm"):
                mask = g.object_mask(name)
                points = g.positions(mask)
                if name in static:
                    prev, nxt = points, points
                else:
                    # The same surface point (the same barycentrics of the same triangle) at
                    # the frames before and after. Where the skin folds inside the elbow a
                    # point lies on two triangles that part in the next frame: those points
                    # are left out, and they must be few.
                    pose = getattr(self.poses, name)
                    inside, _, bary = candidates(points, *pose(n / FPS))
                    self.assertTrue(inside.any(axis=1).all(), "%s at frame %d" % (name, n))

                    def at(time, inside=inside, bary=bary, pose=pose):
                        v, tris = pose(time)
                        where = np.einsum("ptc,tck->ptk", bary, v[tris])
                        where[~inside] = np.nan
                        return where  # points x triangles x 3
                    prev, nxt = at((n - 1) / FPS), at((n + 1) / FPS)
                    spread = np.nan_to_num(np.nanmax(prev, axis=1) - np.nanmin(prev, axis=1)) + \
                        np.nan_to_num(np.nanmax(nxt, axis=1) - np.nanmin(nxt, axis=1))
                    clear = spread.max(axis=1) < 1e-6
                    self.assertGreater(clear.mean(), 0.9, "%s at frame %d" % (name, n))
                    mask = mask.copy()
                    mask[mask] = clear
                    points = points[clear]
                    prev = np.nanmean(prev[clear], axis=1)
                    nxt = np.nanmean(nxt[clear], axis=1)
                now = g.raster(points)
                expected_back = before.raster(prev) - now
                expected_forward = now - after.raster(nxt)
                got_back = np.stack([g.channel("motion.X")[mask], g.channel("motion.Y")[mask]],
                                    axis=1)
                got_forward = np.stack([g.channel("motion.Z")[mask],
                                        g.channel("motion.W")[mask]], axis=1)
                for got, expected, half in ((got_back, expected_back, "X,Y"),
                                            (got_forward, expected_forward, "Z,W")):
                    error = np.abs(got - expected).max()
                    self.assertLess(error, 0.01, "%s, frame %d, motion.%s: off by %.4f pixels"
                                    % (name, n, half, error))
                # Consecutive frames differ where things move: the motion of what moves is
                # its own and the camera's, not the camera's alone.
                own = np.abs(got_back - (before.raster(points) - now)).max()
                if name in static:
                    self.assertLess(own, 0.01, "%s, frame %d" % (name, n))
                else:
                    # (The short block is slowest at the top of its hop, 0.2 pixels.)
                    self.assertGreater(own, 0.1, "%s, frame %d" % (name, n))

    def test_the_sweeping_spot_points_where_its_time_says(self):
        for n in range(FIRST, LAST + 1):
            with open(self.path("out", "shot.lights.%04d.json" % n)) as f:
                lights = {l["name"]: l for l in json.load(f)["lights"]}
            a = math.radians(lerp_keys(shot.SWEEP_PITCH, n / FPS))
            # -z turned about +x by a.
            expected = [0.0, math.sin(a), -math.cos(a)]
            for got, want in zip(lights["sweep"]["direction"], expected):
                self.assertAlmostEqual(got, want, places=5, msg="frame %d" % n)

    def test_motion_blur_changed_the_frames(self):
        for n in range(FIRST, LAST + 1):
            self.assertFalse(fx.same_pixels(self.path("out", "shot.aa.%04d.exr" % n),
                                            self.path("out", "shot.mb.%04d.exr" % n)),
                             "frame %d: dhdr-motionblur left it as it was" % n)

    def test_adaptation_runs_on_across_the_chunks(self):
        stats = self.path(".dhdr-farm", "shot", "stats")
        with open(os.path.join(stats, "tonemap.adapted.json")) as f:
            adapted = json.load(f)["frames"]
        metered = []
        for a in range(FIRST, LAST + 1, CHUNK):
            with open(os.path.join(stats, "tonemap.meter.%d-%d.json" % (a, a + CHUNK - 1))) as f:
                metered += json.load(f)["frames"]
        self.assertEqual([r["frame"] for r in adapted], list(range(FIRST, LAST + 1)))
        self.assertEqual([r["frame"] for r in metered], list(range(FIRST, LAST + 1)))
        # The seed's adapted += (L - adapted)(1 - 0.98^(30 dt)), from the first frame's L, on
        # through the chunk boundary (frame 11 follows frame 10 of the other chunk).
        rate = 1 - 0.98 ** (30 / FPS)
        value = metered[0]["logAverage"]
        for m, r in zip(metered, adapted):
            value += (m["logAverage"] - value) * rate
            self.assertAlmostEqual(r["adapted"], value, delta=1e-12 * value,
                                   msg="frame %d" % r["frame"])
        # The spot coming on brightens the frames; the eye lags behind them.
        self.assertGreater(metered[-1]["logAverage"], 1.3 * metered[0]["logAverage"])
        self.assertLess(adapted[-1]["adapted"], 0.8 * metered[-1]["logAverage"])
        # The PNGs are those of one dhdr-tonemap --adapt over the sequence.
        fx.tool("dhdr-tonemap", "out/shot.bloom.####.exr", "--frames", "%d-%d" % (FIRST, LAST),
                "--adapt", "--fps", "24", "-o", "ref.####.png", cwd=self.dir)
        for n in range(FIRST, LAST + 1):
            self.assertTrue(fx.same_pixels(self.path("ref.%04d.png" % n),
                                           self.path("out", "shot.%04d.png" % n)),
                            "frame %d" % n)


if __name__ == "__main__":
    unittest.main()
