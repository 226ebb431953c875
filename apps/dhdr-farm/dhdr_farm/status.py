"""What became of each chunk: done (its outputs exist), running, failed, or pending, from the
outputs, the tasks' exit status files and (for Slurm) squeue."""

import json
import os

from . import slurm
from .script import paths

FAILED_STATES = {"FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY", "BOOT_FAIL",
                 "DEADLINE", "PREEMPTED"}
RUNNING_STATES = {"RUNNING", "COMPLETING", "CONFIGURING", "SIGNALING", "STAGE_OUT"}


def record_path(state):
    return os.path.join(state, "submission.json")


def write_record(state, record):
    os.makedirs(state, exist_ok=True)
    tmp = record_path(state) + ".tmp%d" % os.getpid()
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(record, f, indent=2)
        f.write("\n")
    os.replace(tmp, record_path(state))


def read_record(state):
    with open(record_path(state), encoding="utf-8") as f:
        return json.load(f)


def _alive(marker):
    """Whether the local process a 'running' marker names still runs on this host."""
    try:
        with open(marker, encoding="utf-8") as f:
            host, pid = f.read().split()
        if host != os.uname().nodename:
            return True
        os.kill(int(pid), 0)
        return True
    except (OSError, ValueError):
        return False


def task_state(plan, job, task, job_id, squeue):
    """'done', 'running', 'failed' or 'pending', and a note (the Slurm reason, the log)."""
    if all(os.path.isfile(p) for p in task.outputs) and not (
            job.kind == "single" and task.todo):
        return "done", ""
    files = paths(plan.state, job.key, task.index)
    rc = None
    if os.path.isfile(files["rc"]):
        with open(files["rc"], encoding="utf-8") as f:
            rc = f.read().strip()
    if job_id is not None and (job_id, task.index) in squeue:
        state, reason = squeue[(job_id, task.index)]
        if state in RUNNING_STATES:
            return "running", ""
        if state in FAILED_STATES:
            if reason == "DependencyNeverSatisfied":
                return "failed", "not run: a chunk it depends on failed"
            if rc is None or rc == "0":
                return "failed", "%s; log %s" % (state.lower(), files["log"])
        elif state != "COMPLETED":
            return "pending", reason if reason not in ("None", "(null)") else ""
    if rc is not None:
        if rc != "0":
            return "failed", "exit status %s; log %s" % (rc, files["log"])
        return "failed", "exit status 0 but outputs missing; log %s" % files["log"]
    if os.path.isfile(files["running"]) and _alive(files["running"]):
        return "running", ""
    return "pending", ""


def collect(plan, job_ids):
    """[(job, [(task, state, note)])] in plan order."""
    squeue = slurm.task_states(list(job_ids.values())) if job_ids else {}
    out = []
    for job in plan.jobs:
        rows = [(t,) + task_state(plan, job, t, job_ids.get(job.key), squeue) for t in job.tasks]
        out.append((job, rows))
    return out


def report(collected, out):
    """Per job one line of counts, then each failed chunk with its frames and why."""
    width = max(len(job.key) for job, _ in collected)
    failed_any, complete = False, True
    for job, rows in collected:
        counts = {s: 0 for s in ("done", "running", "failed", "pending")}
        for _, state, _ in rows:
            counts[state] += 1
        out.write("%-*s  %3d done  %3d running  %3d failed  %3d pending  (%d %s)\n" % (
            width, job.key, counts["done"], counts["running"], counts["failed"],
            counts["pending"], len(rows), "chunk" if len(rows) == 1 else "chunks"))
        failed_any |= counts["failed"] > 0
        complete &= counts["done"] == len(rows)
    for job, rows in collected:
        for task, state, note in rows:
            if state == "failed":
                out.write("  failed: %s chunk %d (frames %s): %s\n" % (
                    job.key, task.index, task.frames, note))
    return complete, failed_any
