"""The batch script of a job: what every task of it runs, under Slurm (sbatch) or locally.
One script per job, written to the state folder, readable, and the same for both engines."""

import os
import shlex

from .frames import FramePattern


def paths(state, job_key, task):
    """Where a task leaves its log, its exit status and its 'running' marker."""
    return {
        "log": os.path.join(state, "logs", "%s.%d.log" % (job_key, task)),
        "rc": os.path.join(state, "tasks", "%s.%d.rc" % (job_key, task)),
        "running": os.path.join(state, "tasks", "%s.%d.running" % (job_key, task)),
    }


def write_script(plan, job, retries):
    """Writes <state>/jobs/<job>.sh and returns its path. The task comes from
    SLURM_ARRAY_TASK_ID (an array), DHDR_FARM_TASK (the local engine) or is 0; tools get
    --threads from SLURM_CPUS_PER_TASK or DHDR_FARM_THREADS (0: every core)."""
    state = plan.state
    for sub in ("jobs", "logs", "tasks", "stats"):
        os.makedirs(os.path.join(state, sub), exist_ok=True)
    for path, text in job.files.items():
        _write_atomically(path, text)
    lines = [
        "#!/bin/bash",
        "# dhdr-farm: pipeline %s, job %s (written by dhdr-farm submit; it is rewritten at "
        "every submission)" % (plan.pipeline.name, job.key),
        "set -u",
        'task="${SLURM_ARRAY_TASK_ID:-${DHDR_FARM_TASK:-0}}"',
        'threads="${SLURM_CPUS_PER_TASK:-${DHDR_FARM_THREADS:-0}}"',
        "cd %s || exit 1" % shlex.quote(plan.pipeline.root),
        'case "$task" in',
    ]
    for t in job.tasks:
        argv = job.command(t)
        # --threads goes before a `--`, after which every argument is an input.
        at = argv.index("--") if "--" in argv else len(argv)
        quoted = " ".join([shlex.quote(a) for a in argv[:at]] + ['--threads "$threads"'] +
                          [shlex.quote(a) for a in argv[at:]])
        lines.append("  %d) frames=%s; command=%s; run() { %s; } ;;" % (
            t.index, t.frames, shlex.quote(" ".join(map(shlex.quote, argv))), quoted))
    lines += [
        '  *) echo "dhdr-farm: job %s has no task $task" >&2; exit 2 ;;' % job.key,
        "esac",
        'tasks=%s' % shlex.quote(os.path.join(state, "tasks")),
        'marker="$tasks/%s.$task.running"; status="$tasks/%s.$task.rc"' % (job.key, job.key),
        'echo "$(hostname) $$" > "$marker"',
        'rm -f "$status"',
        'echo "dhdr-farm: %s task $task, frames $frames, on $(hostname) at $(date -u +%%FT%%TZ)"'
        % job.key,
        'echo "dhdr-farm: $command (with --threads $threads)"',
        "rc=1",
        "for attempt in $(seq 0 %d); do" % retries,
        '  if [ "$attempt" -gt 0 ]; then echo "dhdr-farm: exit status $rc; attempt '
        '$((attempt + 1)) of %d" >&2; fi' % (retries + 1),
        "  run",
        "  rc=$?",
        '  [ "$rc" -eq 0 ] && break',
        "done",
        'echo "$rc" > "$status"',
        'rm -f "$marker"',
        'echo "dhdr-farm: %s task $task finished with exit status $rc at $(date -u +%%FT%%TZ)"'
        % job.key,
        'exit "$rc"',
    ]
    path = os.path.join(state, "jobs", job.key + ".sh")
    _write_atomically(path, "\n".join(lines) + "\n", 0o755)
    return path


def _write_atomically(path, text, mode=None):
    tmp = path + ".tmp%d" % os.getpid()
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    if mode is not None:
        os.chmod(tmp, mode)
    os.replace(tmp, path)


def make_output_folders(plan):
    """The tools refuse an output folder that does not exist; the farm makes them once."""
    for job in plan.jobs:
        if job.kind == "array":
            folder = os.path.dirname(FramePattern(plan.pipeline.resolve(job.stage.output)).text)
            os.makedirs(folder or ".", exist_ok=True)
