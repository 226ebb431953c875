"""The planner without running anything: chunks, frame patterns as the tools read them, which
tasks have work, the dependencies, and the sbatch command lines."""

import json
import os
import sys
import tempfile
import unittest
from unittest import mock

import farm_fixture as fx

sys.path.insert(0, os.path.join(fx.SOURCE, "apps", "dhdr-farm"))

from dhdr_farm import slurm  # noqa: E402
from dhdr_farm.frames import FramePattern, chunks, parse_range  # noqa: E402
from dhdr_farm.pipeline import PipelineError, parse  # noqa: E402
from dhdr_farm.plan import check_inputs, make_plan  # noqa: E402
from dhdr_farm.script import write_script  # noqa: E402

SIZE = fx.SIZE


class Frames(unittest.TestCase):
    def test_chunks_cover_the_range_in_order(self):
        self.assertEqual(chunks(1, 12, 4), [(1, 4), (5, 8), (9, 12)])
        self.assertEqual(chunks(1, 10, 4), [(1, 4), (5, 8), (9, 10)])
        self.assertEqual(chunks(-2, 1, 10), [(-2, 1)])
        self.assertEqual(chunks(7, 7, 3), [(7, 7)])
        with self.assertRaises(ValueError):
            chunks(1, 2, 0)

    def test_patterns_expand_as_the_tools_expand_them(self):
        self.assertEqual(FramePattern("out/a.####.exr").path(7), "out/a.0007.exr")
        self.assertEqual(FramePattern("out/a.%04d.exr").path(12), "out/a.0012.exr")
        self.assertEqual(FramePattern("a.%d.exr").path(12), "a.12.exr")
        self.assertEqual(FramePattern("a.##.exr").path(123), "a.123.exr")
        self.assertEqual(FramePattern("a.####.exr").path(-5), "a.-005.exr")
        # Hashes in a folder name are not a pattern; the file name's last run is.
        self.assertFalse(FramePattern("take#1/a.exr").is_sequence)
        self.assertEqual(FramePattern("take#1/a.#.#.exr").path(3), "take#1/a.#.3.exr")

    def test_pattern_width_is_bounded(self):
        # Issue 21: a pattern wider than the tools' buffer wrote every frame to one file.
        light = {"tool": "dhdr-light", "inputs": ["g.####.exr"], "output": "h.####.exr"}
        for wide in ("h." + "#" * 17 + ".exr", "h.%040d.exr", "h.%0999999999999999999999d.exr"):
            with self.assertRaises(PipelineError, msg=wide) as e:
                parse({"stages": [dict(light, output=wide)]}, "p.json")
            self.assertIn("stages[0]: %r: the frame pattern is wider than 16 digits" % wide,
                          str(e.exception))
        with self.assertRaises(PipelineError) as e:
            parse({"stages": [dict(light, inputs=["g." + "#" * 20 + ".exr"])]}, "p.json")
        self.assertIn("wider than 16 digits", str(e.exception))
        with self.assertRaises(PipelineError) as e:
            parse({"stages": [dict(light, options=["--deep-out", "d.%020d.exr"])]}, "p.json")
        self.assertIn("'d.%020d.exr': the frame pattern is wider", str(e.exception))
        ok = "h." + "#" * 16 + ".exr"
        self.assertEqual(parse({"stages": [dict(light, output=ok)]}, "p.json").stages[0].output, ok)
        self.assertEqual(FramePattern(ok).path(3), "h.0000000000000003.exr")

    def test_ranges(self):
        self.assertEqual(parse_range("1-240"), (1, 240))
        self.assertEqual(parse_range("7"), (7, 7))
        self.assertEqual(parse_range("-5--1"), (-5, -1))
        for bad in ("", "1-", "a-b", "5-1", "1-2000000"):
            with self.assertRaises(ValueError, msg=bad):
                parse_range(bad)


class Pipelines(unittest.TestCase):
    def error(self, doc):
        with self.assertRaises(PipelineError) as e:
            parse(doc, "p.json")
        return str(e.exception)

    def test_outputs_the_tools_refuse_are_refused_before_submitting(self):
        # Issue 48: an image named with '?' is refused by every tool: every chunk failed.
        light = {"tool": "dhdr-light", "inputs": ["g.####.exr"], "output": "h.####.exr"}
        self.assertIn("stages[0]: 'h?.####.exr': the tools cannot write an image whose name "
                      "holds '?'", self.error({"stages": [dict(light, output="h?.####.exr")]}))
        for options in (["--deep-out", "d?.####.exr"], ["--deep-out=d?.####.exr"]):
            self.assertIn("cannot write an image whose name holds '?'",
                          self.error({"stages": [dict(light, options=options)]}))
        # A JSON file may hold '?', as the tools allow.
        gbuffer = {"tool": "dhdr-gbuffer", "inputs": ["s.gltf"], "output": "g.####.exr",
                   "options": ["--lights-out", "l?.####.json"]}
        self.assertEqual(parse({"stages": [gbuffer]}, "p.json").stages[0].options[1],
                         "l?.####.json")

    def test_errors_name_the_stage_and_key(self):
        light = {"tool": "dhdr-light", "inputs": ["g.####.exr"], "output": "h.####.exr"}
        self.assertIn("unknown key 'stage'", self.error({"stage": []}))
        self.assertIn("stages[0]: \"tool\" must be one of",
                      self.error({"stages": [dict(light, tool="oiiotool")]}))
        self.assertIn("stages[0]: \"output\" must be a frame pattern",
                      self.error({"stages": [dict(light, output="h.exr")]}))
        self.assertIn("option -o is set by dhdr-farm",
                      self.error({"stages": [dict(light, options=["-o", "x"])]}))
        self.assertIn("option --frames=1-3 is set by dhdr-farm",
                      self.error({"stages": [dict(light, options=["--frames=1-3"])]}))
        self.assertIn("\"adapt\" is for dhdr-tonemap",
                      self.error({"stages": [dict(light, adapt=True)]}))
        self.assertIn("two stages are called 'light'", self.error({"stages": [light, light]}))
        tonemap = {"tool": "dhdr-tonemap", "inputs": ["h.####.exr"], "output": "p.####.png"}
        self.assertIn("use \"adapt\"",
                      self.error({"stages": [dict(tonemap, options=["--adapt"])]}))
        self.assertIn("\"fps\" goes with", self.error({"stages": [dict(tonemap, fps=30)]}))

    def test_files_that_are_not_json_text_are_errors_naming_them(self):
        # Issue 21: bytes that are not UTF-8 gave an error without the file's name.
        from dhdr_farm.pipeline import load
        with tempfile.TemporaryDirectory() as d:
            for name, data in (("binary.json", b"\xbc\x01\xff{"), ("bom.json", b"\xff\xfe{"),
                               ("deep.json", b"[" * 100000)):
                path = os.path.join(d, name)
                with open(path, "wb") as f:
                    f.write(data)
                with self.assertRaises(PipelineError) as e:
                    load(path)
                self.assertIn(name, str(e.exception))

    def test_motion_blur_is_a_stage(self):
        # Issue 24: gbuffer -> light -> aa -> motionblur -> bloom -> tonemap.
        stages = [{"tool": "dhdr-light", "inputs": ["g.####.exr"], "output": "h.####.exr"},
                  {"tool": "dhdr-motionblur", "inputs": ["h.####.exr"], "output": "m.####.exr",
                   "options": ["--gbuffer", "g.####.exr", "--shutter", "0.5"]}]
        pipeline = parse({"stages": stages}, "p.json")
        self.assertEqual([s.name for s in pipeline.stages], ["light", "motionblur"])

    def test_two_stages_cannot_write_one_output(self):
        # Issue 21: each would overwrite the other's frames with exit 0.
        light = {"tool": "dhdr-light", "inputs": ["g.####.exr"], "output": "out/h.####.exr"}
        bloom = {"tool": "dhdr-bloom", "inputs": ["out/h.####.exr"], "output": "out/h.####.exr"}
        self.assertIn("stages[0] (light) and stages[1] (bloom) both write 'out/h.####.exr'; "
                      "give each stage its own \"output\"",
                      self.error({"stages": [light, bloom]}))
        # Spelt differently, the same files.
        for other in ("./out/h.%04d.exr", "out/../out/h.####.exr"):
            self.assertIn("stages[0] (light) and stages[1] (bloom) both write %r" % other,
                          self.error({"stages": [light, dict(bloom, output=other)]}))
        with self.assertRaises(PipelineError) as e:
            parse({"stages": [dict(light, output="/tmp/farm/h.####.exr"),
                              dict(bloom, output="/tmp/farm/sub/../h.%04d.exr")]},
                  "/elsewhere/p.json")
        self.assertIn("both write", str(e.exception))
        # Other widths or names are other files.
        for other in ("out/h.###.exr", "out/b.####.exr", "h.####.exr"):
            parse({"stages": [light, dict(bloom, output=other)]}, "p.json")

    def test_the_shipped_examples_are_valid(self):
        for name, stages in (("cornell", ["gbuffer", "light", "aa", "bloom", "tonemap"]),
                             ("shot", ["gbuffer", "light", "aa", "motionblur", "bloom",
                                       "tonemap"])):
            path = os.path.join(fx.SOURCE, "docs", "examples", name + ".farm.json")
            with open(path) as f:
                p = parse(json.load(f), path)
            self.assertEqual([s.name for s in p.stages], stages)

    def test_adaptation_runs_at_the_animation_frame_rate(self):
        # Issue 24: frame N shows time N / fps; the eye must adapt at that frame rate too.
        gbuffer = {"tool": "dhdr-gbuffer", "inputs": ["shot.gltf"], "output": "g.####.exr",
                   "options": ["--fps", "30"]}
        tonemap = {"tool": "dhdr-tonemap", "inputs": ["g.####.exr"], "output": "p.####.png",
                   "adapt": True}
        self.assertEqual(parse({"stages": [gbuffer, tonemap]}, "p.json").stages[1].fps, 30.0)
        spelt = dict(gbuffer, options=["--fps=30"])
        self.assertEqual(parse({"stages": [spelt, tonemap]}, "p.json").stages[1].fps, 30.0)
        self.assertEqual(parse({"stages": [gbuffer, dict(tonemap, fps=30)]}, "p.json")
                         .stages[1].fps, 30.0)
        self.assertIn("stages[1] (tonemap) adapts at \"fps\" 24 but stages[0] (gbuffer) "
                      "renders the animation at --fps 30",
                      self.error({"stages": [gbuffer, dict(tonemap, fps=24)]}))
        # Without --fps the G-buffer's frame rate is the tools' default and "fps" stands.
        plain = dict(gbuffer, options=[])
        self.assertEqual(parse({"stages": [plain, dict(tonemap, fps=25)]}, "p.json")
                         .stages[1].fps, 25.0)

    def test_the_schema_knows_every_key(self):
        from dhdr_farm.pipeline import STAGE_KEYS, TOP_KEYS
        with open(os.path.join(fx.SOURCE, "docs", "farm.schema.json")) as f:
            schema = json.load(f)
        self.assertEqual(set(schema["properties"]), TOP_KEYS)
        self.assertEqual(set(schema["$defs"]["stage"]["properties"]), STAGE_KEYS)


class Plans(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="dhdr-plan-")
        doc = fx.pipeline("out")
        doc["stages"][0]["inputs"] = ["scene.gltf"]
        self.path = os.path.join(self.dir, "p.json")
        with open(self.path, "w") as f:
            json.dump(doc, f)
        self.pipeline = parse(doc, self.path)

    def plan(self, first=1, last=12, chunk=4):
        return make_plan(self.pipeline, first, last, chunk, bin_dir="/opt/dhdr/bin")

    def touch(self, *names):
        for name in names:
            path = os.path.join(self.dir, name)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            open(path, "w").close()

    def test_jobs_and_their_dependencies(self):
        plan = self.plan()
        self.assertEqual([j.key for j in plan.jobs], ["gbuffer", "light", "bloom",
                                                      "tonemap-meter", "tonemap-scan",
                                                      "tonemap"])
        deps = {j.key: [(d.key, k) for d, k in j.after] for j in plan.jobs}
        self.assertEqual(deps, {
            "gbuffer": [], "light": [("gbuffer", "aftercorr")],
            "bloom": [("light", "aftercorr")], "tonemap-meter": [("bloom", "aftercorr")],
            "tonemap-scan": [("tonemap-meter", "afterok")],
            "tonemap": [("tonemap-scan", "afterok")]})
        self.assertEqual([(t.first, t.last) for t in plan.job("light").tasks],
                         [(1, 4), (5, 8), (9, 12)])
        self.assertEqual([len(t.outputs) for t in plan.job("light").tasks], [4, 4, 4])
        self.assertEqual(plan.job("tonemap-scan").kind, "single")

    def test_commands_are_the_tools_own_frames(self):
        plan = self.plan()
        light = plan.job("light")
        self.assertEqual(light.command(light.tasks[1]), [
            "/opt/dhdr/bin/dhdr-light", "out/gbuf.####.exr", "-o", "out/hdr.####.exr",
            "--frames", "5-8", "--lights", "lights.####.json"])
        meter = plan.job("tonemap-meter")
        stats = os.path.join(self.dir, ".dhdr-farm", "out", "stats")
        self.assertEqual(meter.command(meter.tasks[2]), [
            "/opt/dhdr/bin/dhdr-tonemap", "out/bloom.####.exr", "--frames", "9-12",
            "--meter-only", "--stats-out", os.path.join(stats, "tonemap.meter.9-12.json")])
        scan = plan.job("tonemap-scan")
        meters = os.path.join(stats, "tonemap.meters.txt")
        self.assertEqual(scan.command(scan.tasks[0]), [
            "/opt/dhdr/bin/dhdr-tonemap", "--scan", "--scan-list", meters, "--fps", "24.0",
            "--stats-out", os.path.join(stats, "tonemap.adapted.json")])
        self.assertEqual(scan.files, {meters: "".join(
            os.path.join(stats, "tonemap.meter.%s.json\n" % r) for r in ("1-4", "5-8", "9-12"))})
        mapping = plan.job("tonemap")
        self.assertEqual(mapping.command(mapping.tasks[0])[-2:],
                         ["--adapt-from", os.path.join(stats, "tonemap.adapted.json")])

    def test_command_lines_fit_whatever_the_chunks(self):
        # Issue 48: the scan's command line named every chunk's metering, past ARG_MAX
        # (2 MiB here) at 30,000 chunks; the names go in a file.
        plan = self.plan(1, 30000, 1)
        scan = plan.job("tonemap-scan")
        self.assertLess(len(" ".join(scan.command(scan.tasks[0]))), 4096)
        (meters, text), = scan.files.items()
        self.assertEqual(len(text.splitlines()), 30000)
        self.assertTrue(text.endswith("tonemap.meter.30000-30000.json\n"))
        script = os.path.join(self.dir, ".dhdr-farm", "out", "jobs", "tonemap-scan.sh")
        self.assertEqual(write_script(plan, scan, 0), script)
        with open(meters) as f:
            self.assertEqual(f.read(), text)
        self.assertLess(os.path.getsize(script), 8192)

    def test_a_million_chunks_are_planned_from_one_listing(self):
        # Issue 48: a stat per output took over a minute; outputs are found by listing their
        # folder once. Which chunks are done still comes from the files.
        self.touch("out/gbuf.0002.exr", "out/gbuf.999999.exr", "out/gbuf.0003.exr.tmp",
                   "out/gbuf.0004.exr/x")
        with mock.patch("os.path.isfile", side_effect=AssertionError("a stat per output")):
            plan = self.plan(1, 1000000, 1)
        gbuffer = plan.job("gbuffer")
        self.assertEqual(len(gbuffer.tasks), 1000000)
        self.assertEqual(len(gbuffer.todo), 999998)
        self.assertEqual([t.todo for t in gbuffer.tasks[:4]], [True, False, True, True])
        self.assertFalse(gbuffer.tasks[999998].todo)
        self.assertEqual(gbuffer.tasks[1].outputs, [os.path.join(self.dir, "out/gbuf.0002.exr")])
        self.assertTrue(all(t.todo for t in plan.job("light").tasks[:3]))

    def test_inputs_that_look_like_options_follow_double_dash(self):
        doc = fx.pipeline("out")
        doc["stages"][0]["inputs"] = ["-scene.gltf"]
        doc["stages"][1]["inputs"] = ["-g.####.exr"]
        doc["stages"][3]["inputs"] = ["-b.####.exr"]
        plan = make_plan(parse(doc, self.path), 1, 4, 4, bin_dir="/b")
        gbuffer, light = plan.job("gbuffer"), plan.job("light")
        self.assertEqual(gbuffer.command(gbuffer.tasks[0]), [
            "/b/dhdr-gbuffer", "-o", "out/gbuf.####.exr", "--frames", "1-4", "--size", SIZE,
            "--", "-scene.gltf"])
        self.assertEqual(light.command(light.tasks[0])[-2:], ["--", "-g.####.exr"])
        for key in ("tonemap-meter", "tonemap"):
            job = plan.job(key)
            self.assertEqual(job.command(job.tasks[0])[-2:], ["--", "-b.####.exr"], key)
        # The script's --threads goes before the `--`.
        with open(write_script(plan, light, 0)) as f:
            self.assertIn('--threads "$threads" -- \'-g.####.exr\'; }', f.read())
        # Inputs that do not begin with '-' stay first, as before.
        self.assertEqual(plan.job("bloom").command(plan.job("bloom").tasks[0])[1],
                         "out/hdr.####.exr")

    def test_each_adapting_stage_names_its_own_statistics(self):
        doc = fx.pipeline("out")
        second = dict(doc["stages"][3], name="tonemap2", output="out/frame2.####.png")
        doc["stages"].append(second)
        plan = make_plan(parse(doc, self.path), 1, 4, 4, bin_dir="/b")
        for key in ("tonemap", "tonemap2"):
            meter, scan = plan.job(key + "-meter"), plan.job(key + "-scan")
            self.assertTrue(meter.command(meter.tasks[0])[-1].endswith(
                "%s.meter.1-4.json" % key), meter.command(meter.tasks[0]))
            self.assertTrue(scan.command(scan.tasks[0])[3].endswith("%s.meters.txt" % key))
            mapping = plan.job(key)
            self.assertTrue(mapping.command(mapping.tasks[0])[-1].endswith(
                "%s.adapted.json" % key))

    def test_complete_chunks_are_skipped_and_remade_inputs_redo_what_follows(self):
        for f in range(1, 13):
            self.touch("out/gbuf.%04d.exr" % f)
        for f in range(5, 9):
            self.touch("out/hdr.%04d.exr" % f, "out/bloom.%04d.exr" % f)
        plan = self.plan()
        self.assertEqual([t.index for t in plan.job("gbuffer").todo], [])
        self.assertEqual([t.index for t in plan.job("light").todo], [0, 2])
        self.assertEqual([t.index for t in plan.job("bloom").todo], [0, 2])
        self.assertNotIn(plan.job("gbuffer"), plan.submitted)
        # A job with nothing to do is no dependency.
        self.assertEqual(plan.dependencies(plan.job("light")), [])
        # One frame of the G-buffer missing: its chunk and chunk 1 of every stage after it.
        os.remove(os.path.join(self.dir, "out/gbuf.0006.exr"))
        plan = self.plan()
        self.assertEqual([t.index for t in plan.job("gbuffer").todo], [1])
        self.assertEqual([t.index for t in plan.job("light").todo], [0, 1, 2])
        self.assertEqual([t.index for t in plan.job("bloom").todo], [0, 1, 2])

    def test_adaptation_is_redone_when_any_metering_is(self):
        for f in range(1, 13):
            self.touch(*["out/%s.%04d.%s" % (s, f, e) for s, e in
                         (("gbuf", "exr"), ("hdr", "exr"), ("bloom", "exr"), ("frame", "png"))])
        stats = ".dhdr-farm/out/stats/"
        self.touch(*[stats + "tonemap.meter.%s.json" % r for r in ("1-4", "5-8", "9-12")])
        with open(os.path.join(self.dir, stats, "tonemap.adapted.json"), "w") as f:
            json.dump({"adapt": True, "frames": [{"frame": i} for i in range(1, 13)]}, f)
        self.assertEqual(self.plan().submitted, [])
        # Statistics of other frames (the range grew): scanned again, every chunk mapped again.
        plan = self.plan(1, 16)
        self.assertEqual(len(plan.job("tonemap-scan").todo), 1)
        self.assertEqual([t.index for t in plan.job("tonemap").todo], [0, 1, 2, 3])
        self.assertEqual([t.index for t in plan.job("tonemap-meter").todo], [3])
        # One picture missing: that chunk alone.
        os.remove(os.path.join(self.dir, "out/frame.0010.png"))
        plan = self.plan()
        self.assertEqual([j.key for j in plan.submitted], ["tonemap"])
        self.assertEqual([t.index for t in plan.job("tonemap").todo], [2])

    def test_sbatch_command_lines(self):
        self.touch(*["out/gbuf.%04d.exr" % f for f in range(1, 5)])
        plan = self.plan()
        light = plan.job("light")
        argv = slurm.sbatch_argv(plan, light, "/s/light.sh", [("101", "aftercorr")],
                                 partition="render", max_running=2, cpus=8)
        logs = os.path.join(self.dir, ".dhdr-farm", "out", "logs")
        self.assertEqual(argv, [
            "sbatch", "--parsable", "--job-name=dhdr.out.light", "--chdir=" + self.dir,
            "--requeue", "--kill-on-invalid-dep=yes", "--array=0-2%2",
            "--output=" + os.path.join(logs, "light.%a.log"), "--partition=render",
            "--cpus-per-task=8", "--dependency=aftercorr:101", "/s/light.sh"])
        scan = plan.job("tonemap-scan")
        argv = slurm.sbatch_argv(plan, scan, "/s/scan.sh", [("102", "afterok")])
        self.assertNotIn("--array", " ".join(argv))
        self.assertIn("--output=" + os.path.join(logs, "tonemap-scan.0.log"), argv)
        self.assertIn("--dependency=afterok:102", argv)
        self.assertEqual(slurm.array_spec([0, 1, 2, 5, 7, 8]), "0-2,5,7-8")
        self.assertEqual(slurm.array_spec([3], 4), "3%4")

    def test_submission_order_and_ids(self):
        self.touch(*["out/gbuf.%04d.exr" % f for f in range(1, 13)])
        plan = self.plan()
        calls = []

        def sbatch(argv):
            calls.append(argv)
            return str(200 + len(calls))
        ids = slurm.submit(plan, {j.key: "/s/%s.sh" % j.key for j in plan.jobs}, sbatch=sbatch)
        self.assertEqual(list(ids), ["light", "bloom", "tonemap-meter", "tonemap-scan",
                                     "tonemap"])
        deps = [[a for a in argv if a.startswith("--dependency")] for argv in calls]
        self.assertEqual(deps, [[], ["--dependency=aftercorr:201"],
                                ["--dependency=aftercorr:202"], ["--dependency=afterok:203"],
                                ["--dependency=afterok:204"]])

    def test_missing_inputs_are_found_before_submitting(self):
        missing = check_inputs(self.plan(1, 2))
        self.assertEqual(len(missing), 2, missing)
        self.assertIn("scene.gltf (stage gbuffer)", missing[0])
        self.assertIn("lights.0001.json (stage light)", missing[1])
        self.touch("scene.gltf", "lights.0001.json", "lights.0002.json")
        self.assertEqual(check_inputs(self.plan(1, 2)), [])

    def test_files_an_earlier_stage_writes_through_its_options_are_made(self):
        # An animated shot's lights, one file a frame from dhdr-gbuffer --lights-out, are the
        # lighting stage's --lights: none exists before the G-buffer stage runs.
        doc = fx.pipeline("out", lights="out/posed")
        doc["stages"][0]["inputs"] = ["scene.gltf"]
        doc["stages"][0]["options"] += ["--lights-out", "out/posed.####.json"]
        self.touch("scene.gltf")
        plan = make_plan(parse(doc, self.path), 1, 2, 4)
        self.assertEqual(check_inputs(plan), [])
        # Written by no stage: still missing.
        doc["stages"][0]["options"][-1] = "out/other.####.json"
        plan = make_plan(parse(doc, self.path), 1, 2, 4)
        self.assertEqual(len(check_inputs(plan)), 1)
        self.assertIn("posed.0001.json (stage light)", check_inputs(plan)[0])


if __name__ == "__main__":
    unittest.main()
