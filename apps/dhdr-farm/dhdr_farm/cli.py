"""dhdr-farm submit | status | plan: the command line (docs/farm.md)."""

import argparse
import io
import os
import shutil
import sys
import time

from . import VERSION, local, slurm
from . import status as status_mod
from .frames import parse_range
from .pipeline import PipelineError, load
from .plan import check_inputs, default_state, make_plan
from .script import make_output_folders, paths, write_script

EXIT_OK, EXIT_FAILURE, EXIT_USAGE, EXIT_INCOMPLETE = 0, 1, 2, 3
# Tasks of a job that `plan` prints at each end without --all-tasks.
PLAN_TASKS = 5
# Frames per task, and the local engine's processes, when the command line does not say.
DEFAULT_CHUNK = 10
DEFAULT_LOCAL_PROCESSES = 1


def _tools_folder(given):
    """--bin, else the folder dhdr-farm lives in when the tools are beside it (an install, a
    build tree), else None: the tools are found on PATH by the jobs."""
    if given:
        return os.path.abspath(given)
    here = os.path.dirname(os.path.abspath(sys.argv[0]))
    if os.path.isfile(os.path.join(here, "dhdr-tonemap")):
        return here
    return None


def _parser():
    p = argparse.ArgumentParser(
        prog="dhdr-farm",
        description="Runs a dhdr pipeline (docs/farm.md) over a frame range: on Slurm, one "
                    "job array per stage, chunk i of a stage starting when chunk i of the "
                    "stage before has finished (aftercorr); or the same plan as local "
                    "processes. Resubmitting skips chunks whose outputs all exist.",
        epilog="Examples:\n"
               "  dhdr-farm submit shot.farm.json --frames 1-240 --chunk 8 --wait\n"
               "  dhdr-farm submit shot.farm.json --frames 1-240 --engine local -j 2\n"
               "  dhdr-farm status shot.farm.json\n"
               "  dhdr-farm plan shot.farm.json --frames 1-12 --chunk 4\n"
               "Exit status: 0 done (or submitted, without --wait), 1 a chunk failed or an "
               "input is missing, 2 usage error, 3 (status) not finished yet.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--version", action="version", version="dhdr-farm " + VERSION)
    sub = p.add_subparsers(dest="command", required=True)

    def common(s, frames_required):
        s.add_argument("pipeline", metavar="PIPELINE.json", help="the pipeline file")
        s.add_argument("--frames", metavar="A-B", required=frames_required,
                       help="frames to run" + ("" if frames_required else
                                               " (default: those of the last submission)"))
        s.add_argument("--chunk", type=int, metavar="N",
                       help="frames per task, run by one process (default %d%s)" % (
                           DEFAULT_CHUNK, "" if frames_required else ", or the last submission's"))
        s.add_argument("--state", metavar="DIR",
                       help="where job scripts, logs and statistics go (default "
                            ".dhdr-farm/<name> beside the pipeline file; on a cluster it "
                            "must be on the shared filesystem)")
        s.add_argument("--bin", metavar="DIR",
                       help="folder of the dhdr tools (default: dhdr-farm's own folder when "
                            "they are there, else PATH on the nodes)")

    s = sub.add_parser("submit", help="plan and run or submit the pipeline")
    common(s, True)
    s.add_argument("--engine", choices=("slurm", "local"), default="slurm",
                   help="slurm (default): sbatch job arrays; local: processes here")
    s.add_argument("--partition", metavar="P", help="Slurm partition (default: the cluster's)")
    s.add_argument("--max-running", "-j", type=int, metavar="K",
                   help="at most K chunks of a stage at once (Slurm: the array's %%K); local "
                        "engine: at most K processes in all (default " + str(DEFAULT_LOCAL_PROCESSES) + ")")
    s.add_argument("--retries", type=int, default=0, metavar="R",
                   help="run a failing chunk up to R more times before it fails (default %(default)s)")
    s.add_argument("--cpus", type=int, metavar="C",
                   help="cores per task: Slurm's --cpus-per-task, and the tools' --threads "
                        "(default: Slurm's 1 per task; locally every core)")
    s.add_argument("--wait", action="store_true",
                   help="Slurm: block until the pipeline has finished, then print the status; "
                        "exit 1 if a chunk failed for good (the local engine always waits)")
    s.add_argument("-q", "--quiet", action="store_true", help="errors only")

    s = sub.add_parser("status", help="chunks done, running, failed and pending per stage")
    common(s, False)

    s = sub.add_parser("plan", help="print the jobs and the sbatch command lines, submit nothing")
    common(s, True)
    s.add_argument("--partition", metavar="P")
    s.add_argument("--max-running", "-j", type=int, metavar="K")
    s.add_argument("--cpus", type=int, metavar="C")
    s.add_argument("--all-tasks", action="store_true",
                   help="print every task's command line (default: the first and last %d of "
                        "each job)" % PLAN_TASKS)
    return p


def _error(message, status=EXIT_FAILURE):
    sys.stderr.write("dhdr-farm: error: %s\n" % message)
    return status


def _plan(args, first, last, chunk):
    pipeline = load(args.pipeline)
    return make_plan(pipeline, first, last, chunk, args.state, _tools_folder(args.bin))


def _check_numbers(args):
    for name in ("chunk", "max_running", "cpus"):
        v = getattr(args, name, None)
        if v is not None and v < 1:
            raise ValueError("--%s must be at least 1" % name.replace("_", "-"))
    if getattr(args, "retries", 0) < 0:
        raise ValueError("--retries must be 0 or more")


def submit(args):
    first, last = parse_range(args.frames)
    plan = _plan(args, first, last, args.chunk or DEFAULT_CHUNK)
    say = (lambda m: None) if args.quiet else (lambda m: sys.stdout.write(m + "\n"))
    missing = check_inputs(plan)
    if missing:
        return _error("inputs missing: " + "; ".join(missing[:5]) +
                      (" and %d more" % (len(missing) - 5) if len(missing) > 5 else ""))
    if plan.pipeline.stages and _tools_folder(args.bin) is None and \
            shutil.which(plan.pipeline.stages[0].tool) is None:
        return _error("%s is not in --bin or on PATH" % plan.pipeline.stages[0].tool)
    record = {"pipeline": plan.pipeline.path, "engine": args.engine, "frames": [first, last],
              "chunk": plan.chunk, "bin": _tools_folder(args.bin), "jobs": {},
              "submitted": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    todo = plan.submitted
    if not todo:
        status_mod.write_record(plan.state, record)
        say("nothing to do: every chunk's outputs exist (%d frames, %s)" % (
            last - first + 1, ", ".join(j.key for j in plan.jobs)))
        return EXIT_OK
    make_output_folders(plan)
    scripts = {job.key: write_script(plan, job, args.retries) for job in todo}
    for job in plan.jobs:
        if job.todo:
            say("%-16s %d of %d chunks to run" % (job.key, len(job.todo), len(job.tasks)))
        else:
            say("%-16s done (outputs exist)" % job.key)

    if args.engine == "local":
        def progress(key, rc):
            # Failures are errors: printed under -q too.
            job_key, task = key
            if rc is None:
                sys.stderr.write("dhdr-farm: %s chunk %d: not run, a chunk it depends on "
                                 "failed\n" % (job_key, task))
            elif rc != 0:
                sys.stderr.write("dhdr-farm: %s chunk %d: failed with exit status %d (log %s)\n"
                                 % (job_key, task, rc, paths(plan.state, job_key, task)["log"]))
        status_mod.write_record(plan.state, record)
        local.run(plan, scripts, args.max_running or DEFAULT_LOCAL_PROCESSES, args.cpus or 0, report=progress)
    else:
        ids = slurm.submit(plan, scripts, args.partition, args.max_running, args.cpus)
        record["jobs"] = ids
        status_mod.write_record(plan.state, record)
        for key, jid in ids.items():
            say("submitted %s as Slurm job %s" % (key, jid))
        if not args.wait:
            return EXIT_OK
        slurm.wait(list(ids.values()))
    fresh = make_plan(plan.pipeline, first, last, plan.chunk, plan.state,
                      _tools_folder(args.bin))
    complete, _ = status_mod.report(status_mod.collect(fresh, record["jobs"]),
                                    io.StringIO() if args.quiet else sys.stdout)
    return EXIT_OK if complete else EXIT_FAILURE


def status(args):
    pipeline = load(args.pipeline)
    state = os.path.abspath(args.state or default_state(pipeline))
    try:
        record = status_mod.read_record(state)
    except (OSError, ValueError, RecursionError):
        record = None
    # A record damaged by hand or by a full disk is as good as none.
    if not (isinstance(record, dict) and isinstance(record.get("frames"), list)
            and len(record["frames"]) == 2
            and all(isinstance(f, int) for f in record["frames"])
            and isinstance(record.get("chunk", DEFAULT_CHUNK), int)):
        record = None
    if record is None and not args.frames:
        return _error("%s: never submitted (no %s); give --frames to check the outputs" % (
            args.pipeline, status_mod.record_path(state)))
    first, last = parse_range(args.frames) if args.frames else record["frames"]
    chunk = args.chunk or (record["chunk"] if record else DEFAULT_CHUNK)
    bin_dir = _tools_folder(args.bin) if args.bin or not record else record.get("bin")
    plan = make_plan(pipeline, first, last, chunk, state, bin_dir)
    jobs = record["jobs"] if record and record.get("engine") == "slurm" else {}
    sys.stdout.write("pipeline %s, frames %d-%d in chunks of %d%s\n" % (
        pipeline.name, first, last, chunk,
        ", submitted %s (%s)" % (record["submitted"], record["engine"]) if record else ""))
    complete, failed = status_mod.report(status_mod.collect(plan, jobs), sys.stdout)
    return EXIT_OK if complete else EXIT_FAILURE if failed else EXIT_INCOMPLETE


def show_plan(args):
    first, last = parse_range(args.frames)
    plan = _plan(args, first, last, args.chunk or DEFAULT_CHUNK)
    out = []
    for job in plan.jobs:
        deps = ", ".join("%s %s" % (kind, d.key) for d, kind in job.after) or "none"
        out.append("%s: %s, %d of %d tasks to run, after: %s\n" % (
            job.key, job.kind, len(job.todo), len(job.tasks), deps))
        # A million chunks would print a million lines a stage: the first and last few.
        shown = job.tasks if args.all_tasks or len(job.tasks) <= 2 * PLAN_TASKS else \
            job.tasks[:PLAN_TASKS] + [None] + job.tasks[-PLAN_TASKS:]
        for t in shown:
            if t is None:
                out.append("  ... %d more tasks (--all-tasks lists them)\n" % (
                    len(job.tasks) - 2 * PLAN_TASKS))
                continue
            out.append("  task %d frames %s%s: %s\n" % (
                t.index, t.frames, "" if t.todo else " (done)", " ".join(job.command(t))))
    sys.stdout.write("".join(out))
    ids = {}
    for job in plan.submitted:
        ids[job.key] = "<%s>" % job.key
        deps = [(ids[d.key], kind) for d, kind in plan.dependencies(job)]
        argv = slurm.sbatch_argv(plan, job, os.path.join(plan.state, "jobs", job.key + ".sh"),
                                 deps, args.partition, args.max_running, args.cpus)
        sys.stdout.write(" ".join(argv) + "\n")
    return EXIT_OK


def main(argv=None):
    args = _parser().parse_args(argv)
    try:
        _check_numbers(args)
        return {"submit": submit, "status": status, "plan": show_plan}[args.command](args)
    except ValueError as e:
        return _error(str(e), EXIT_USAGE)
    except PipelineError as e:
        return _error(str(e))
    except slurm.SlurmError as e:
        return _error(str(e))
    except OSError as e:
        return _error("%s: %s" % (e.filename or "dhdr-farm", e.strerror or e))
    except KeyboardInterrupt:
        return _error("interrupted (jobs already submitted keep running; dhdr-farm status "
                      "shows them)")
