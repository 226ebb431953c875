"""The Slurm engine: one sbatch per job with work (a job array per stage), dependencies by
job id, and squeue for the state of each task. No daemon of ours: Slurm schedules."""

import subprocess
import time

from .script import paths


class SlurmError(Exception):
    pass


def array_spec(indices, max_running=None):
    """'0-3', '1,4-6' and '%K': the task ids of an array, ranges folded."""
    parts, run = [], []
    for i in sorted(indices):
        if run and i == run[-1] + 1:
            run.append(i)
            continue
        if run:
            parts.append(str(run[0]) if len(run) == 1 else "%d-%d" % (run[0], run[-1]))
        run = [i]
    if run:
        parts.append(str(run[0]) if len(run) == 1 else "%d-%d" % (run[0], run[-1]))
    spec = ",".join(parts)
    return spec + ("%%%d" % max_running if max_running else "")


def sbatch_argv(plan, job, script, dependency_ids, partition=None, max_running=None,
                cpus=None):
    """The sbatch command line of `job`. `dependency_ids` holds (job id, 'aftercorr' |
    'afterok') of the jobs it waits for."""
    log = paths(plan.state, job.key, 0)["log"]
    argv = ["sbatch", "--parsable",
            "--job-name=dhdr.%s.%s" % (plan.pipeline.name, job.key),
            "--chdir=%s" % plan.pipeline.root,
            # Node failure or preemption puts the task back in the queue; a failing frame is
            # retried by the script itself (--retries).
            "--requeue",
            # A task whose dependency failed is cancelled rather than left pending forever.
            "--kill-on-invalid-dep=yes"]
    if job.kind == "array":
        argv.append("--array=%s" % array_spec([t.index for t in job.todo], max_running))
        argv.append("--output=%s" % log.replace(".0.log", ".%a.log"))
    else:
        argv.append("--output=%s" % log)
    if partition:
        argv.append("--partition=%s" % partition)
    if cpus:
        argv.append("--cpus-per-task=%d" % cpus)
    if dependency_ids:
        argv.append("--dependency=" + ",".join("%s:%s" % (kind, i) for i, kind in dependency_ids))
    argv.append(script)
    return argv


def run_sbatch(argv):
    try:
        out = subprocess.run(argv, capture_output=True, text=True, timeout=120)
    except FileNotFoundError:
        raise SlurmError("sbatch not found: is this a Slurm submit host (slurm-client)?")
    except subprocess.TimeoutExpired:
        raise SlurmError("sbatch did not answer in 120 s")
    if out.returncode != 0:
        raise SlurmError("sbatch failed (exit status %d): %s" % (out.returncode,
                                                                out.stderr.strip()))
    # --parsable: "jobid" or "jobid;cluster".
    return out.stdout.strip().split(";")[0]


def submit(plan, scripts, partition=None, max_running=None, cpus=None, sbatch=run_sbatch):
    """Submits every job with work in order; returns {job key: job id}. When an sbatch fails,
    the jobs already submitted are cancelled so that nothing half-planned runs."""
    ids = {}
    for job in plan.submitted:
        deps = [(ids[d.key], kind) for d, kind in plan.dependencies(job)]
        argv = sbatch_argv(plan, job, scripts[job.key], deps, partition, max_running, cpus)
        try:
            ids[job.key] = sbatch(argv)
        except SlurmError:
            if ids:
                subprocess.run(["scancel"] + list(ids.values()), capture_output=True)
            raise
    return ids


def task_states(job_ids):
    """{(job id, task) : (state, reason)} from squeue, for every task Slurm still knows
    (finished ones for MinJobAge, 300 s by default). A single job is task 0."""
    if not job_ids:
        return {}
    out = subprocess.run(["squeue", "-h", "-r", "-t", "all", "-o", "%i|%T|%r",
                          "-j", ",".join(job_ids)], capture_output=True, text=True)
    if out.returncode != 0:
        # squeue refuses ids that have aged out of the controller: ask one by one.
        if len(job_ids) > 1:
            states = {}
            for i in job_ids:
                states.update(task_states([i]))
            return states
        return {}
    states = {}
    for line in out.stdout.splitlines():
        fields = line.strip().split("|")
        if len(fields) != 3:
            continue
        jid, state, reason = fields
        if "_" in jid:
            base, task = jid.split("_", 1)
            if not task.isdigit():  # a pending remainder such as 12_[4-7%2]
                continue
            states[(base, int(task))] = (state, reason)
        else:
            states[(jid, 0)] = (state, reason)
    return states


ACTIVE = {"PENDING", "RUNNING", "CONFIGURING", "COMPLETING", "REQUEUED", "RESIZING",
          "SUSPENDED", "REQUEUE_HOLD", "REQUEUE_FED", "SIGNALING", "STAGE_OUT", "STOPPED"}


def active(job_ids):
    """Whether Slurm still has a task of these jobs to run (pending remainders included)."""
    if not job_ids:
        return False
    out = subprocess.run(["squeue", "-h", "-t", "all", "-o", "%T", "-j", ",".join(job_ids)],
                         capture_output=True, text=True)
    if out.returncode != 0:
        return any(active([i]) for i in job_ids) if len(job_ids) > 1 else False
    return any(s.strip() in ACTIVE for s in out.stdout.splitlines())


def wait(job_ids, poll=1.0, on_poll=None):
    """Polls squeue until no task of `job_ids` is pending or running (sbatch --wait's client
    polls slowly: about 10 s however short the job)."""
    while active(job_ids):
        if on_poll:
            on_poll()
        time.sleep(poll)
