"""The local engine: the same plan and scripts as Slurm, run as processes on this machine.
Dependencies mean what Slurm makes them mean: with aftercorr task i starts when task i of
the job before has succeeded (or, where that job has no task i, when all of it has);
afterok waits for the whole job. A failed task's dependents never start."""

import os
import subprocess
import time

from .script import paths


def run(plan, scripts, max_running=1, threads=0, poll=0.05, report=None):
    """Runs every task with work, at most `max_running` at a time; returns
    {(job key, task): exit status or None when it never started (a dependency failed)}."""
    pending = [(job, t) for job in plan.submitted for t in job.todo]
    status = {}  # (job key, task) -> exit status
    running = {}  # (job key, task) -> Popen
    env_base = dict(os.environ, DHDR_FARM_THREADS=str(threads))

    def state_of(job, index):
        """'ok', 'failed' or None (not finished) for a task of a submitted job."""
        rc = status.get((job.key, index))
        if rc is None:
            return None
        return "ok" if rc == 0 else "failed"

    def ready(job, task):
        """True to start, False to wait, None when it can never start."""
        for dep, kind in plan.dependencies(job):
            if kind == "aftercorr" and job.kind == "array" and dep.kind == "array" and \
                    any(t.index == task.index for t in dep.todo):
                wanted = [task.index]
            else:
                wanted = [t.index for t in dep.todo]
            states = [state_of(dep, i) for i in wanted]
            if "failed" in states or any((dep.key, i) in status and status[(dep.key, i)] is
                                         None for i in wanted):
                return None
            if None in states:
                return False
        return True

    while pending or running:
        for key, proc in list(running.items()):
            rc = proc.poll()
            if rc is not None:
                status[key] = rc
                del running[key]
                if report:
                    report(key, rc)
        progressed = False
        for item in list(pending):
            job, task = item
            r = ready(job, task)
            if r is None:
                status[(job.key, task.index)] = None
                pending.remove(item)
                progressed = True
                if report:
                    report((job.key, task.index), None)
            elif r and len(running) < max_running:
                log = paths(plan.state, job.key, task.index)["log"]
                env = dict(env_base, DHDR_FARM_TASK=str(task.index))
                with open(log, "w") as out:
                    running[(job.key, task.index)] = subprocess.Popen(
                        ["/bin/bash", scripts[job.key]], stdout=out, stderr=subprocess.STDOUT,
                        stdin=subprocess.DEVNULL, env=env, cwd=plan.pipeline.root)
                pending.remove(item)
                progressed = True
        if not progressed:
            time.sleep(poll)
    return status
