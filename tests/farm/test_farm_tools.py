"""dhdr-farm run as a user runs it: the local engine, and a real single-node Slurm cluster
(slurm_cluster.py). Both must give the PNGs of the chain run by the tools directly, with
adaptation in one --adapt run over the whole sequence, bit for bit."""

import json
import os
import re
import shutil
import tempfile
import unittest

import farm_fixture as fx
from slurm_cluster import SlurmCluster


class FarmCase(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="dhdr-farm-test-")
        os.chmod(cls.dir, 0o755)
        fx.write_lights(cls.dir)
        fx.reference(cls.dir)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def path(self, *parts):
        return os.path.join(self.dir, *parts)

    def assertSameAsReference(self, out, frames=fx.FRAMES):
        for f in frames:
            for stage in ("hdr.%04d.exr", "frame.%04d.png"):
                name = stage % f
                self.assertTrue(os.path.isfile(self.path(out, name)), name)
                self.assertTrue(fx.same_pixels(self.path("ref", name), self.path(out, name)),
                                "%s/%s differs from the one-process run" % (out, name))
        # The scanned statistics are the one-process run's.
        with open(self.path("ref", "stats.json")) as f:
            ref = json.load(f)
        with open(self.path(".dhdr-farm", out, "stats", "tonemap.adapted.json")) as f:
            got = json.load(f)
        self.assertEqual([r["adapted"] for r in ref["frames"]],
                         [r["adapted"] for r in got["frames"]])

    def assertStatus(self, text, job, done, running, failed, pending):
        m = re.search(r"^%s\s+(\d+) done\s+(\d+) running\s+(\d+) failed\s+(\d+) pending" %
                      re.escape(job), text, re.M)
        self.assertIsNotNone(m, "no status line for %s in:\n%s" % (job, text))
        self.assertEqual(tuple(map(int, m.groups())), (done, running, failed, pending),
                         "%s in:\n%s" % (job, text))


class LocalEngine(FarmCase):
    def test_the_plan_run_locally_is_the_one_process_run(self):
        pipeline = fx.write_pipeline(self.dir, "local")
        r = fx.farm("submit", pipeline, "--frames", "1-12", "--chunk", "4", "--engine",
                    "local", "-j", "2", cwd=self.dir)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertSameAsReference("local")
        # The adaptation mattered: the first bright frame is mapped darker than the last.
        r = fx.farm("submit", pipeline, "--frames", "1-12", "--chunk", "4", "--engine",
                    "local", cwd=self.dir)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("nothing to do", r.stdout)
        # A chunk's output removed: only that chunk, and everything the adaptation needs after
        # it, runs again.
        os.remove(self.path("local", "hdr.0006.exr"))
        r = fx.farm("submit", pipeline, "--frames", "1-12", "--chunk", "4", "--engine",
                    "local", cwd=self.dir)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertRegex(r.stdout, r"gbuffer\s+done")
        self.assertRegex(r.stdout, r"light\s+1 of 3 chunks to run")
        self.assertRegex(r.stdout, r"tonemap-meter\s+1 of 3 chunks to run")
        self.assertRegex(r.stdout, r"tonemap\s+3 of 3 chunks to run")
        self.assertSameAsReference("local")

    def test_adaptation_changes_the_pictures(self):
        # Without adaptation, frame 7 (the first bright one) would be metered on its own; the
        # adapted one keeps the dim exposure and comes out brighter. Holds the test to frames
        # where adaptation makes a difference.
        fx.tool("dhdr-tonemap", "ref/bloom.0007.exr", "-o", "alone.0007.png", cwd=self.dir)
        self.assertFalse(fx.same_pixels(self.path("alone.0007.png"),
                                        self.path("ref", "frame.0007.png")))

    def test_bad_pipelines_are_usage_errors_naming_the_key(self):
        bad = self.path("bad.farm.json")
        with open(bad, "w") as f:
            json.dump({"stages": [{"tool": "dhdr-light", "inputs": ["a.####.exr"],
                                   "output": "b.exr"}]}, f)
        r = fx.farm("submit", bad, "--frames", "1-2", "--engine", "local", cwd=self.dir)
        self.assertEqual(r.returncode, 1)
        self.assertIn("stages[0]: \"output\" must be a frame pattern", r.stderr)
        r = fx.farm("submit", self.path("local.farm.json"), "--frames", "3-1", "--engine",
                    "local", cwd=self.dir)
        self.assertEqual(r.returncode, 2)
        self.assertIn("before the first", r.stderr)
        # An input no stage makes and that is not there: refused before anything runs.
        with open(bad, "w") as f:
            json.dump(fx.pipeline("missing", lights="nolights"), f)
        r = fx.farm("submit", bad, "--frames", "1-2", "--engine", "local", cwd=self.dir)
        self.assertEqual(r.returncode, 1)
        self.assertIn("inputs missing", r.stderr)
        self.assertFalse(os.path.exists(self.path("missing")))


@unittest.skipUnless(os.geteuid() == 0, "starting munged and slurmd needs root")
class Slurm(FarmCase):
    def test_pipeline_on_slurm_restart_and_a_failing_frame(self):
        fx.write_lights(self.dir, stem="badlights", broken=6)
        with SlurmCluster() as cluster:
            env = cluster.env
            pipeline = fx.write_pipeline(self.dir, "slurm")
            r = fx.farm("submit", pipeline, "--frames", "1-12", "--chunk", "4",
                        "--max-running", "2", "--wait", cwd=self.dir, env=env)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            self.assertEqual(len(re.findall(r"submitted \S+ as Slurm job", r.stdout)), 6)
            self.assertSameAsReference("slurm")

            # Resubmission: every output exists, nothing is submitted.
            r = fx.farm("submit", pipeline, "--frames", "1-12", "--chunk", "4", "--wait",
                        cwd=self.dir, env=env)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("nothing to do", r.stdout)
            self.assertNotIn("Slurm job", r.stdout)
            r = fx.farm("status", pipeline, cwd=self.dir, env=env)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            self.assertStatus(r.stdout, "tonemap", 3, 0, 0, 0)

            # Frame 6's lights file is broken: its light chunk fails (after one retry), the
            # other chunks finish, and what depends on it never runs.
            failing = fx.write_pipeline(self.dir, "failing", lights="badlights")
            r = fx.farm("submit", failing, "--frames", "1-12", "--chunk", "4", "--retries",
                        "1", "--wait", cwd=self.dir, env=env)
            self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
            r = fx.farm("status", failing, cwd=self.dir, env=env)
            self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
            self.assertStatus(r.stdout, "gbuffer", 3, 0, 0, 0)
            self.assertStatus(r.stdout, "light", 2, 0, 1, 0)
            self.assertStatus(r.stdout, "bloom", 2, 0, 1, 0)
            self.assertStatus(r.stdout, "tonemap-meter", 2, 0, 1, 0)
            self.assertStatus(r.stdout, "tonemap-scan", 0, 0, 1, 0)
            self.assertStatus(r.stdout, "tonemap", 0, 0, 3, 0)
            self.assertRegex(r.stdout, r"failed: light chunk 1 \(frames 5-8\): exit status 1")
            with open(self.path(".dhdr-farm", "failing", "logs", "light.1.log")) as f:
                log = f.read()
            self.assertIn("attempt 2 of 2", log)
            self.assertIn("badlights.0006.json", log)
            for f in (1, 2, 3, 4, 9, 10, 11, 12):
                self.assertTrue(os.path.isfile(self.path("failing", "bloom.%04d.exr" % f)))
            self.assertFalse(os.path.exists(self.path("failing", "frame.0001.png")))

            # Mended and resubmitted: only what is missing runs, and the result is the
            # one-process run's.
            shutil.copy(self.path("lights.0006.json"), self.path("badlights.0006.json"))
            r = fx.farm("submit", failing, "--frames", "1-12", "--chunk", "4", "--wait",
                        cwd=self.dir, env=env)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            self.assertRegex(r.stdout, r"gbuffer\s+done")
            self.assertRegex(r.stdout, r"light\s+1 of 3 chunks to run")
            self.assertSameAsReference("failing")


if __name__ == "__main__":
    unittest.main()
