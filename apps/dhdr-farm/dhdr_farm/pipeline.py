"""The pipeline file (docs/farm.md, docs/farm.schema.json): the stages in order, each a dhdr
tool with its inputs, output pattern and options. Every error names the file and the key."""

import json
import os
import re

from .frames import MAX_WIDTH, FramePattern

TOOLS = ("dhdr-gbuffer", "dhdr-light", "dhdr-aa", "dhdr-motionblur", "dhdr-bloom", "dhdr-tonemap")
STAGE_KEYS = {"name", "tool", "inputs", "output", "options", "adapt", "fps"}
TOP_KEYS = {"$schema", "name", "stages"}
# Options the farm sets itself: in a stage's options they would contradict the plan.
RESERVED = {"-o", "--output", "--frames", "--threads"}
# Options of the tools whose value is a file they write.
OUTPUT_OPTIONS = {"--lights-out", "--deep-out", "--stats-out"}
TONEMAP_RESERVED = {"--adapt", "--meter-only", "--scan", "--adapt-from", "--stats-out", "--fps"}


class PipelineError(Exception):
    pass


class Stage:
    def __init__(self, name, tool, inputs, output, options, adapt, fps):
        self.name, self.tool, self.inputs, self.output = name, tool, inputs, output
        self.options, self.adapt, self.fps = options, adapt, fps
        self.fps_given = False  # "fps" written in the file, not the default

    def __repr__(self):
        return "Stage(%s, %s)" % (self.name, self.tool)


class Pipeline:
    def __init__(self, path, name, stages):
        self.path = os.path.abspath(path)
        # Paths in the file are relative to its folder; every job runs there.
        self.root = os.path.dirname(self.path)
        self.name = name
        self.stages = stages

    def resolve(self, path):
        return path if os.path.isabs(path) else os.path.join(self.root, path)


def _option_number(options, name):
    """The value of `name N` or `name=N` among a stage's options as a float, or None when it
    is not there or not a number (the tool itself says what is wrong with it then)."""
    for i, o in enumerate(options):
        if o == name and i + 1 < len(options):
            text = options[i + 1]
        elif o.startswith(name + "="):
            text = o.split("=", 1)[1]
        else:
            continue
        try:
            return float(text)
        except ValueError:
            return None
    return None


def _strings(value):
    return isinstance(value, list) and all(isinstance(v, str) for v in value)


def load(path):
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except OSError as e:
        raise PipelineError("%s: cannot be read (%s)" % (path, e.strerror))
    except json.JSONDecodeError as e:
        raise PipelineError("%s: not JSON (line %d: %s)" % (path, e.lineno, e.msg))
    except (UnicodeDecodeError, RecursionError, ValueError) as e:
        raise PipelineError("%s: not a JSON text file (%s)" % (path, e))
    return parse(doc, path)


def parse(doc, path="pipeline.json"):
    def fail(message):
        raise PipelineError("%s: %s" % (path, message))

    if not isinstance(doc, dict):
        fail("the pipeline is a JSON object with \"stages\"")
    unknown = sorted(set(doc) - TOP_KEYS)
    if unknown:
        fail("unknown key %s (known: name, stages)" % ", ".join(map(repr, unknown)))
    stem = os.path.basename(path)
    stem = stem[: -len(".json")] if stem.endswith(".json") else stem
    name = doc.get("name", stem)
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z0-9_.-]+", name):
        fail("\"name\" must be letters, digits, '_', '.' or '-' (it names the jobs)")
    raw = doc.get("stages")
    if not isinstance(raw, list) or not raw:
        fail("\"stages\" must be a non-empty list")
    stages, names = [], set()
    for i, s in enumerate(raw):
        where = "stages[%d]" % i

        def bad(message, where=where):
            fail("%s: %s" % (where, message))

        if not isinstance(s, dict):
            bad("a stage is an object with tool, inputs and output")
        unknown = sorted(set(s) - STAGE_KEYS)
        if unknown:
            bad("unknown key %s (known: %s)" % (", ".join(map(repr, unknown)),
                                               ", ".join(sorted(STAGE_KEYS))))
        tool = s.get("tool")
        if tool not in TOOLS:
            bad("\"tool\" must be one of %s, not %r" % (", ".join(TOOLS), tool))
        stage_name = s.get("name", tool[len("dhdr-"):])
        if not isinstance(stage_name, str) or not re.fullmatch(r"[A-Za-z0-9_-]+", stage_name):
            bad("\"name\" must be letters, digits, '_' or '-'")
        if stage_name in names:
            bad("two stages are called %r; give them different \"name\"s" % stage_name)
        names.add(stage_name)
        inputs = s.get("inputs")
        if not _strings(inputs) or not inputs:
            bad("\"inputs\" must be a non-empty list of paths (frame patterns like "
                "out/light.####.exr where they change per frame)")
        output = s.get("output")
        if not isinstance(output, str) or not FramePattern(output).is_sequence:
            bad("\"output\" must be a frame pattern (out/%s.####.exr), not %r"
                % (stage_name, output))
        options = s.get("options", [])
        if not _strings(options):
            bad("\"options\" must be a list of strings, one per word (\"--size\", \"640x360\")")
        for text in inputs + [output] + options:
            if FramePattern(text).width > MAX_WIDTH:
                bad("%r: the frame pattern is wider than %d digits (frame numbers have at "
                    "most 9)" % (text, MAX_WIDTH))
        # The tools refuse to write an image whose name holds '?' (OpenImageIO reads what
        # follows it as options): every chunk would fail at run time.
        written = [output] + [o for j, o in enumerate(options)
                              if j > 0 and options[j - 1] in OUTPUT_OPTIONS] + \
            [o.split("=", 1)[1] for o in options if o.split("=", 1)[0] in OUTPUT_OPTIONS and
             "=" in o]
        for text in written:
            if "?" in text and not text.lower().endswith(".json"):
                bad("%r: the tools cannot write an image whose name holds '?' (OpenImageIO "
                    "takes what follows it for options); choose a name without '?'" % text)
        reserved = RESERVED | (TONEMAP_RESERVED if tool == "dhdr-tonemap" else set())
        for o in options:
            if o.split("=", 1)[0] in reserved:
                bad("option %s is set by dhdr-farm (%s)" % (
                    o, "use \"adapt\" and \"fps\"" if o.split("=", 1)[0] in TONEMAP_RESERVED
                    else "-o is \"output\"; --frames and --threads come from the submission"))
        adapt = s.get("adapt", False)
        if not isinstance(adapt, bool):
            bad("\"adapt\" must be true or false")
        if adapt and tool != "dhdr-tonemap":
            bad("\"adapt\" is for dhdr-tonemap stages")
        if adapt and len(inputs) != 1:
            bad("a dhdr-tonemap stage takes one input pattern")
        fps = s.get("fps", 24.0)
        if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not 0 < fps <= 1000:
            bad("\"fps\" must be a number in (0, 1000]")
        if "fps" in s and not adapt:
            bad("\"fps\" goes with \"adapt\": true")
        stages.append(Stage(stage_name, tool, inputs, output, options, adapt, float(fps)))
        stages[-1].fps_given = "fps" in s
    # Frame N of an animated scene shows time N / fps (dhdr-gbuffer --fps, default 24), and
    # eye adaptation steps 1 / fps a frame: the two must agree, or the eye adapts slower or
    # faster than the shot plays. An adapting dhdr-tonemap without "fps" takes the
    # G-buffer's.
    for i, stage in enumerate(stages):
        if stage.tool != "dhdr-gbuffer":
            continue
        shot_fps = _option_number(stage.options, "--fps")
        if shot_fps is None:
            continue
        for j, other in enumerate(stages):
            if not other.adapt:
                continue
            if not other.fps_given:
                other.fps = shot_fps
            elif other.fps != shot_fps:
                fail("stages[%d] (%s) adapts at \"fps\" %g but stages[%d] (%s) renders the "
                     "animation at --fps %g; give both the same frame rate" % (
                         j, other.name, other.fps, i, stage.name, shot_fps))
    # Two stages writing one pattern would overwrite each other's frames (and each would
    # find the other's chunks complete). The same files are the same pattern however it is
    # spelt: out/a.####.exr, ./out/a.%04d.exr.
    root = os.path.dirname(os.path.abspath(path))
    writers = {}
    for i, stage in enumerate(stages):
        p = FramePattern(os.path.normpath(os.path.join(root, stage.output)))
        key = (p.prefix, p.suffix, max(p.width, 1))  # %d pads as # does
        if key in writers:
            j = writers[key]
            fail("stages[%d] (%s) and stages[%d] (%s) both write %r; give each stage its own "
                 "\"output\"" % (j, stages[j].name, i, stage.name, stage.output))
        writers[key] = i
    return Pipeline(path, name, stages)
