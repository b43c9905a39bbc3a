"""Many jobs, each a world stepped and measured, run in this process, on a dask.distributed
cluster (a LocalCluster of worker processes, or dask-scheduler and dask-worker on several
machines), or one job per task of a scheduler's job array (python3 -m pfx.sweep), with the
same results, bit for bit, wherever they run.

A job is a dict:

  world        the bytes of World.to_bytes(), or the path of a saved world (World.save,
               pfx_sim --save); or instead
  urdf         the path of a URDF robot, loaded into a new world with
    world_param  WorldParam fields (default: gravity (0, 0, -9.80665), time_step 1/240),
    urdf_param   UrdfLoadParam fields (fixed_base, ...),
    ground       True for a ground box with its top at z = 0 (as pfx_sim --ground),
    joint_targets  {joint name: position}: position drives held through the run;
  steps        how many steps to run (a whole number, 0 or more), required;
  measure      names from MEASURES (default ["state_hash"]);
  name         any label, copied into the result.

Or a job runs pfx_bench, the benchmark, once (pfx.bench_sweep builds such jobs from a
sweep over scenes, time steps and iterations):

  bench        pfx_bench's arguments (a list of strings), instead of world, urdf, steps
               and measure;
  program      the pfx_bench to run (default: bench_program());
  name         as above.

A result is a dict: "name" (when the job has one), "steps", and one entry per measure; for a
pfx_bench job, "name" and "tsv": the table pfx_bench printed, its header line first.
run() checks every job before any runs: a bad job raises ValueError naming the job and the
field, and nothing runs. Paths are read where the job runs: on a cluster, every worker must
see them (a shared folder), or send bytes instead.
"""
import json
import os
import sys

import numpy as np

import pfx

# What a job can report of its world after the run.
MEASURES = {
    "state_hash": lambda world, model: f"{world.state_hash():016x}",
    "simulated_time": lambda world, model: world.simulated_time,
    "num_bodies": lambda world, model: world.num_bodies,
    "max_penetration": lambda world, model: float(world.stats.max_penetration),
    "max_joint_gap": lambda world, model: float(world.stats.max_joint_gap),
    "energy": lambda world, model: world.conserved_quantities()["energy"],
    "positions": lambda world, model: world.positions.copy(),
    "orientations": lambda world, model: world.orientations.copy(),
    "joint_positions": lambda world, model: model.joint_states()[0],
}
# Measures that need the URDF model (a job with "urdf").
_MODEL_MEASURES = {"joint_positions"}
_JOB_FIELDS = {"world", "urdf", "world_param", "urdf_param", "ground", "joint_targets", "steps",
               "measure", "name"}
_BENCH_JOB_FIELDS = {"bench", "program", "name"}
_URDF_ONLY_FIELDS = ("world_param", "urdf_param", "ground", "joint_targets")

# Where a task's index comes from when --task-index is not given, in this order: pfx's own,
# then what Slurm job arrays and Kubernetes indexed Jobs set.
TASK_INDEX_VARIABLES = ("PFX_TASK_INDEX", "SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX")


def check_job(job, index=0):
    """Raises ValueError naming job `index` and what is wrong with it."""
    def bad(what):
        raise ValueError(f"job {index}: {what}")

    if not isinstance(job, dict):
        bad(f"is a {type(job).__name__}, not a dict")
    if "bench" in job:
        _check_bench_job(job, bad)
        return
    unknown = sorted(set(job) - _JOB_FIELDS)
    if unknown:
        bad(f"unknown field {unknown[0]!r} (fields: {', '.join(sorted(_JOB_FIELDS))})")
    if ("world" in job) == ("urdf" in job):
        bad("give either 'world' (bytes or a saved world's path) or 'urdf' (a path)")
    if "world" in job:
        if not isinstance(job["world"], (bytes, str, os.PathLike)):
            bad(f"'world' is a {type(job['world']).__name__}, not bytes or a path")
        given = [field for field in _URDF_ONLY_FIELDS if field in job]
        if given:
            bad(f"{given[0]!r} goes with 'urdf'; a saved world brings its own")
    elif not isinstance(job["urdf"], (str, os.PathLike)):
        bad(f"'urdf' is a {type(job['urdf']).__name__}, not a path")
    for field in ("world_param", "urdf_param", "joint_targets"):
        if field in job and not isinstance(job[field], dict):
            bad(f"{field!r} is a {type(job[field]).__name__}, not a dict")
    steps = job.get("steps")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 0:
        bad(f"'steps' must be a whole number, 0 or more, not {steps!r}")
    measure = job.get("measure", ["state_hash"])
    if isinstance(measure, str) or not all(isinstance(name, str) for name in measure):
        bad(f"'measure' must be a list of names, not {measure!r}")
    for name in measure:
        if name not in MEASURES:
            bad(f"unknown measure {name!r} (measures: {', '.join(MEASURES)})")
        if name in _MODEL_MEASURES and "urdf" not in job:
            bad(f"measure {name!r} needs a job with 'urdf'")


def _check_bench_job(job, bad):
    unknown = sorted(set(job) - _BENCH_JOB_FIELDS)
    if unknown:
        bad(f"unknown field {unknown[0]!r} for a pfx_bench job (fields: "
            f"{', '.join(sorted(_BENCH_JOB_FIELDS))})")
    arguments = job["bench"]
    if isinstance(arguments, str) or not isinstance(arguments, (list, tuple)) or \
            not all(isinstance(argument, str) for argument in arguments):
        bad(f"'bench' must be a list of pfx_bench's arguments (strings), not {arguments!r}")
    if "program" in job and not isinstance(job["program"], (str, os.PathLike)):
        bad(f"'program' is a {type(job['program']).__name__}, not a path")


def bench_program():
    """The pfx_bench a job runs when it names none: $PFX_BENCH, else bin/pfx_bench of the
    build tree this module was built in, else pfx_bench on the PATH (None without one)."""
    import shutil

    if os.environ.get("PFX_BENCH"):
        return os.environ["PFX_BENCH"]
    build = os.path.dirname(os.path.dirname(os.path.realpath(pfx._core.__file__)))
    beside = os.path.join(os.path.dirname(build), "bin", "pfx_bench")
    return beside if os.access(beside, os.X_OK) else shutil.which("pfx_bench")


def _run_bench_job(job):
    import subprocess

    program = job.get("program") or bench_program()
    if not program:
        raise RuntimeError("no pfx_bench: set PFX_BENCH or give the job a 'program'")
    done = subprocess.run([os.fspath(program), *job["bench"]], capture_output=True, text=True)
    if done.returncode != 0:
        said = done.stderr.strip().splitlines()
        raise RuntimeError(f"pfx_bench {' '.join(job['bench'])}: exit status {done.returncode}"
                           + (f": {said[-1]}" if said else ""))
    result = {"name": job["name"]} if "name" in job else {}
    result["tsv"] = done.stdout
    return result


def _build(job):
    """The job's world, and its URDF model or None."""
    if "world" in job:
        source = job["world"]
        if isinstance(source, bytes):
            return pfx.World.from_bytes(source, num_threads=1), None
        world = pfx.World()
        world.load(os.fspath(source), num_threads=1)
        return world, None
    param = {"gravity": (0, 0, -9.80665), "time_step": 1 / 240}
    param.update(job.get("world_param", {}))
    world = pfx.World(pfx.WorldParam(**param))
    if job.get("ground", False):
        world.add_body(pfx.Shape.box((50, 50, 0.5)), pfx.BodyInit(mass=0, position=(0, 0, -0.5)))
    model = world.load_urdf(os.fspath(job["urdf"]), pfx.UrdfLoadParam(**job.get("urdf_param", {})))
    for joint, target in job.get("joint_targets", {}).items():
        model.set_joint_command(joint, pfx.JointDrive.POSITION, target)
    return world, model


def run_job(job):
    """Builds, steps and measures one job (checked first); returns its result dict."""
    check_job(job)
    if "bench" in job:
        return _run_bench_job(job)
    world, model = _build(job)
    world.step(int(job["steps"]))
    result = {"name": job["name"]} if "name" in job else {}
    result["steps"] = int(job["steps"])
    for name in job.get("measure", ["state_hash"]):
        result[name] = MEASURES[name](world, model)
    return result


def run(jobs, client=None):
    """Runs every job and returns their results in the jobs' order: here, one after the
    other, or, given a dask.distributed Client, spread over its workers. Every job is
    checked before any runs."""
    jobs = list(jobs)
    for index, job in enumerate(jobs):
        check_job(job, index)
    if client is None:
        return [run_job(job) for job in jobs]
    # pure=False: two equal jobs are still two tasks, each with its own result.
    return client.gather(client.map(run_job, jobs, pure=False))


def table(results):
    """The results' scalar entries (numbers, hashes, names) as a numpy structured array, one
    row per result; array-valued measures (positions, ...) are left out."""
    results = list(results)
    if not results:
        return np.zeros(0)
    columns = [key for key, value in results[0].items() if np.ndim(value) == 0]
    return np.rec.fromrecords([tuple(r[key] for key in columns) for r in results], names=columns)


def resolve_task_index(given, num_jobs, environ=None):
    """The index of the job to run: `given` (--task-index), else the first of
    TASK_INDEX_VARIABLES set in the environment. Raises ValueError, saying where the index
    came from, when there is none or it is not a whole number in [0, num_jobs)."""
    environ = os.environ if environ is None else environ
    source, text = "--task-index", given
    if text is None:
        for variable in TASK_INDEX_VARIABLES:
            if environ.get(variable, "") != "":
                source, text = variable, environ[variable]
                break
        else:
            raise ValueError("no task index: give --task-index or set one of " +
                             ", ".join(TASK_INDEX_VARIABLES))
    text = str(text).strip()
    if not (text.lstrip("-").isdigit() and text.count("-") <= 1 and not text.startswith("+")):
        raise ValueError(f"task index {text!r} (from {source}) is not a whole number")
    index = int(text)
    if index < 0:
        raise ValueError(f"task index {index} (from {source}) is negative")
    if index >= num_jobs:
        raise ValueError(f"task index {index} (from {source}) is out of range: the job list "
                         f"has {num_jobs} jobs, 0 to {num_jobs - 1}")
    return index


def _json_ready(value):
    return value.tolist() if isinstance(value, np.ndarray) else value


def main(argv=None):
    """python3 -m pfx.sweep JOBS.json [--task-index N] [--out RESULT.json]: runs one job of a
    JSON list (paths only: JSON holds no bytes) and writes its result as JSON, with the task
    index and the job; see resolve_task_index for where the index comes from."""
    import argparse

    parser = argparse.ArgumentParser(prog="python3 -m pfx.sweep", description=main.__doc__)
    parser.add_argument("jobs", help="a JSON file holding a list of jobs")
    parser.add_argument("--task-index", help="which job (default: from the environment)")
    parser.add_argument("--out", help="write the result here (default: standard output)")
    options = parser.parse_args(argv)
    try:
        with open(options.jobs, encoding="utf-8") as file:
            jobs = json.load(file)
        if not isinstance(jobs, list):
            raise ValueError(f"{options.jobs}: holds a {type(jobs).__name__}, not a list of jobs")
        index = resolve_task_index(options.task_index, len(jobs))
        check_job(jobs[index], index)
        result = {"task": index, "job": jobs[index], **run_job(jobs[index])}
    except (OSError, ValueError, RuntimeError) as error:  # pfx.Error, a failed pfx_bench run
        print(f"pfx.sweep: {error}", file=sys.stderr)
        return 2 if isinstance(error, ValueError) and not isinstance(error, pfx.Error) else 1
    text = json.dumps({key: _json_ready(value) for key, value in result.items()})
    if options.out:
        with open(options.out, "w", encoding="utf-8") as file:
            file.write(text + "\n")
    else:
        print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
