"""The plan of a submission: jobs (a job array per stage; metering, scan and mapping for a
stage with adaptation), their tasks (one chunk of frames each), which of them still have
work, and the dependencies between them. Both engines run the same plan."""

import json
import os

from .frames import FramePattern, chunks, exists_complete
from .pipeline import OUTPUT_OPTIONS


class Task:
    """Chunk `index`, frames [first, last]. Its outputs are `outputs` (absolute paths) or the
    frames of `pattern`; it has work (`todo`) unless all exist, or when `todo` says so."""

    __slots__ = ("index", "first", "last", "_outputs", "_pattern", "todo")

    def __init__(self, index, first, last, outputs=None, exists=exists_complete, pattern=None,
                 todo=None):
        self.index, self.first, self.last = index, first, last
        self._outputs, self._pattern = outputs, pattern
        self.todo = todo if todo is not None else not all(exists(p) for p in self.outputs)

    @property
    def outputs(self):
        if self._outputs is None:
            return [self._pattern.path(f) for f in range(self.first, self.last + 1)]
        return self._outputs

    @property
    def frames(self):
        return "%d-%d" % (self.first, self.last)


class Job:
    """`kind` is 'array' (one task per chunk, task ids = chunk indices) or 'single' (task 0).
    `after` holds (job, 'aftercorr' | 'afterok'): aftercorr lets task i start when task i of
    the job before has finished; afterok waits for the whole job."""

    def __init__(self, key, stage, kind, tasks, command, after, files=None):
        self.key, self.stage, self.kind = key, stage, kind
        self.tasks, self.command, self.after = tasks, command, after
        # Files the job's tasks read that the submission writes: {path: text}.
        self.files = files or {}

    @property
    def todo(self):
        return [t for t in self.tasks if t.todo]

    def __repr__(self):
        return "Job(%s, %d/%d to do)" % (self.key, len(self.todo), len(self.tasks))


class Plan:
    def __init__(self, pipeline, first, last, chunk, state, jobs):
        self.pipeline, self.first, self.last, self.chunk = pipeline, first, last, chunk
        self.state, self.jobs = state, jobs

    def job(self, key):
        return next(j for j in self.jobs if j.key == key)

    @property
    def submitted(self):
        """The jobs with work, in order (a job with nothing to do is not submitted: its
        outputs are already there)."""
        return [j for j in self.jobs if j.todo]

    def dependencies(self, job):
        """What `job` waits for: only the jobs that are submitted too."""
        return [(d, kind) for d, kind in job.after if d.todo]


def default_state(pipeline):
    return os.path.join(pipeline.root, ".dhdr-farm", pipeline.name)


def tool_path(bin_dir, tool):
    return os.path.join(bin_dir, tool) if bin_dir else tool


def _covers(path, frames):
    """Whether the statistics file `path` holds adapted luminances of exactly `frames`."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
        return doc.get("adapt") is True and [r["frame"] for r in doc["frames"]] == frames
    except (OSError, ValueError, KeyError, TypeError):
        return False


class _Listing:
    """exists_complete over many files: each folder listed once (a million chunks are a
    million outputs; a stat each took most of a minute)."""

    def __init__(self):
        self.folders = {}

    def files(self, folder):
        found = self.folders.get(folder)
        if found is None:
            found = set()
            try:
                with os.scandir(folder or ".") as entries:
                    found = {e.name for e in entries if e.is_file()}
            except OSError:
                pass
            self.folders[folder] = found
        return found

    def __call__(self, path):
        folder, name = os.path.split(path)
        return name in self.files(folder)


def tool_command(exe, inputs, rest):
    """The tool's command line: an input that begins with '-' would be read as an option, so
    then the inputs follow `--`, which ends the options (docs/tools.md)."""
    if any(i.startswith("-") for i in inputs):
        return [exe] + rest + ["--"] + inputs
    return [exe] + inputs + rest


def make_plan(pipeline, first, last, chunk, state=None, bin_dir=None):
    """Jobs for frames [first, last] in chunks of `chunk` frames. A task has work when one of
    its outputs is missing or a task it depends on has work (its inputs are being remade)."""
    state = os.path.abspath(state or default_state(pipeline))
    ranges = chunks(first, last, chunk)
    jobs = []
    upstream = None  # the job whose task i makes the inputs of the next stage's task i
    exists = _Listing()

    def frame_tasks(pattern):
        """A task per chunk whose outputs are `pattern`'s frames: which exist is read from
        one listing of their folder (a pattern is in the file's name)."""
        p = FramePattern(pipeline.resolve(pattern))
        folder, head = os.path.split(p.prefix)
        done = set()
        for name in exists.files(folder):
            digits = name[len(head):len(name) - len(p.suffix)] if p.suffix else name[len(head):]
            if name.startswith(head) and name.endswith(p.suffix) and \
                    digits.lstrip("-").isdigit() and \
                    os.path.join(folder, name) == p.path(int(digits)):
                done.add(int(digits))
        tasks = []
        for i, (a, b) in enumerate(ranges):
            todo = a not in done if a == b else not all(f in done for f in range(a, b + 1))
            tasks.append(Task(i, a, b, pattern=p, todo=todo))
        return tasks

    def cascade(job, dep):
        # aftercorr: task i is redone when task i before it is; afterok: when any is.
        for t in job.tasks:
            if dep.kind == "single" or job.kind == "single":
                t.todo = t.todo or bool(dep.todo)
            else:
                t.todo = t.todo or dep.tasks[t.index].todo

    for stage in pipeline.stages:
        exe = tool_path(bin_dir, stage.tool)
        if not stage.adapt:
            def command(task, stage=stage, exe=exe):
                return tool_command(exe, stage.inputs, ["-o", stage.output, "--frames",
                                                        task.frames] + stage.options)
            tasks = frame_tasks(stage.output)
            job = Job(stage.name, stage, "array", tasks, command,
                      [(upstream, "aftercorr")] if upstream else [])
            if upstream:
                cascade(job, upstream)
            jobs.append(job)
            upstream = job
            continue

        # Adaptation across the whole sequence: meter each chunk, scan all statistics in
        # frame order, map each chunk with the scanned values.
        stats = os.path.join(state, "stats")
        meter_name = stage.name + ".meter.%d-%d.json"
        meter_file = lambda a, b, name=meter_name: stats + os.sep + name % (a, b)
        adapted = os.path.join(stats, "%s.adapted.json" % stage.name)
        # The metering files, one a line: thousands of chunks' names exceed what a command
        # line holds (ARG_MAX).
        meter_list = os.path.join(stats, "%s.meters.txt" % stage.name)

        # Each command binds its stage's names: the loop rebinds them for the next stage.
        def meter_command(task, stage=stage, exe=exe, meter_file=meter_file):
            return tool_command(exe, stage.inputs, [
                "--frames", task.frames, "--meter-only", "--stats-out",
                meter_file(task.first, task.last)] + stage.options)
        meter = Job(stage.name + "-meter", stage, "array",
                    [Task(i, a, b, [meter_file(a, b)],
                          todo=meter_name % (a, b) not in exists.files(stats))
                     for i, (a, b) in enumerate(ranges)],
                    meter_command, [(upstream, "aftercorr")] if upstream else [])
        if upstream:
            cascade(meter, upstream)

        def scan_command(task, stage=stage, exe=exe, meter_list=meter_list, adapted=adapted):
            return [exe, "--scan", "--scan-list", meter_list, "--fps", repr(stage.fps),
                    "--stats-out", adapted]
        scan_task = Task(0, first, last, [adapted], exists)
        scan_task.todo = scan_task.todo or not _covers(adapted, list(range(first, last + 1)))
        scan = Job(stage.name + "-scan", stage, "single", [scan_task], scan_command,
                   [(meter, "afterok")],
                   {meter_list: "".join(meter_file(a, b) + "\n" for a, b in ranges)})
        cascade(scan, meter)

        def map_command(task, stage=stage, exe=exe, adapted=adapted):
            return tool_command(exe, stage.inputs, ["-o", stage.output, "--frames", task.frames,
                                                    "--adapt-from", adapted] + stage.options)
        mapping = Job(stage.name, stage, "array",
                      frame_tasks(stage.output), map_command, [(scan, "afterok")])
        cascade(mapping, scan)
        jobs += [meter, scan, mapping]
        upstream = mapping
    return Plan(pipeline, first, last, chunk, state, jobs)


def check_inputs(plan):
    """Plain inputs and patterned inputs no earlier stage makes must exist for every frame:
    a missing scene is an error at submission, not a failed job an hour later. An earlier
    stage makes its output and the files its output options name: an animated shot's lights,
    posed per frame by dhdr-gbuffer --lights-out lights.####.json, are read by dhdr-light
    --lights lights.####.json before any of them exists."""
    made = set()
    missing = []
    for stage in plan.pipeline.stages:
        # Option values with a frame pattern are per-frame inputs too (--lights
        # lights.####.json), but for the options that name outputs.
        patterned = [o for i, o in enumerate(stage.options) if FramePattern(o).is_sequence and
                     not (i > 0 and stage.options[i - 1] in OUTPUT_OPTIONS)]
        for text in stage.inputs + patterned:
            p = FramePattern(plan.pipeline.resolve(text))
            if p.is_sequence and p.text in made:
                continue
            frames = range(plan.first, plan.last + 1) if p.is_sequence else [None]
            for f in frames:
                path = p.path(f)
                if not os.path.exists(path):
                    missing.append("%s (stage %s)" % (path, stage.name))
                    break
        made.add(FramePattern(plan.pipeline.resolve(stage.output)).text)
        for i, o in enumerate(stage.options[1:], 1):
            if stage.options[i - 1] in OUTPUT_OPTIONS:
                made.add(FramePattern(plan.pipeline.resolve(o)).text)
    return missing
