"""pfx_bench's error-against-time sweep split into pfx.sweep jobs: one pfx_bench run per
scene, time step and iteration count (each with every engine, sub-step and thread count
asked for), run here or on a dask.distributed cluster, and gathered into the table pfx_bench
writes, rows in its order. The error is pfx_bench's own: each job is a pfx_bench run.

    python3 -m pfx.bench_sweep --scene chain,spinner --dt 1/60,1/240 --iterations 5,10 \\
        [--engine pfx,bullet] [--substeps N,...] [--threads N,...] [--seconds S] \\
        [--scheduler tcp://HOST:8786 | --local-workers N] [--out results.tsv]

For the scenes that step the engines side by side (pyramid, chain, urdf, ...); the scenes
pfx_bench runs apart (rays, batch, characters, ...) do not sweep time steps and iterations.
Every worker must see the pfx_bench it runs (PFX_BENCH, or the build beside the module).
"""
import sys

import pfx.sweep

# The TSV's columns (pfx_bench's writeTsvHeader): the run's wall time per simulated second
# is the one column that differs from run to run.
COLUMNS = ("scene", "engine", "variant", "dt", "substeps", "iterations", "threads",
           "wall_s_per_sim_s", "metric", "value")
WALL_TIME_COLUMN = COLUMNS.index("wall_s_per_sim_s")


def _parse_time_step(text):
    numerator, _, denominator = str(text).partition("/")
    try:
        value = float(numerator) / float(denominator or 1)
    except (ValueError, ZeroDivisionError):
        value = float("nan")
    if not 0 < value < float("inf"):
        raise ValueError(f"time step {text!r} is not a positive number like 1/60 or 0.0166")
    return str(text)


def _list(name, values, check):
    values = [values] if isinstance(values, (str, int, float)) else list(values)
    if not values:
        raise ValueError(f"{name}: no value given")
    return [check(value) for value in values]


def _positive_int(name):
    def check(value):
        if isinstance(value, bool) or not str(value).isdigit() or int(value) < 1:
            raise ValueError(f"{name}: {value!r} is not a positive whole number")
        return str(int(value))
    return check


def _name(kind):
    def check(value):
        if not isinstance(value, str) or not value or "," in value:
            raise ValueError(f"{kind} {value!r} is not one {kind}'s name")
        return value
    return check


def jobs(scenes, time_steps, iterations, engines=None, substeps=None, threads=None,
         seconds=None, program=None):
    """The sweep's pfx.sweep jobs, one per scene, time step and iteration count in that
    order. Time steps as pfx_bench reads them ("1/60", "0.0166"); engines, substeps and
    threads are lists passed to every run (default: pfx_bench's). Raises ValueError naming
    what is wrong."""
    scenes = _list("scenes", scenes, _name("scene"))
    time_steps = _list("time_steps", time_steps, _parse_time_step)
    iterations = _list("iterations", iterations, _positive_int("iterations"))
    common = []
    if engines is not None:
        common += ["--engine", ",".join(_list("engines", engines, _name("engine")))]
    if substeps is not None:
        common += ["--substeps", ",".join(_list("substeps", substeps, _positive_int("substeps")))]
    if threads is not None:
        common += ["--threads", ",".join(_list("threads", threads, _positive_int("threads")))]
    if seconds is not None:
        if isinstance(seconds, (bool, str)) or not 0 < float(seconds) < float("inf"):
            raise ValueError(f"seconds: {seconds!r} is not a positive duration")
        common += ["--seconds", repr(float(seconds))]
    built = []
    for scene in scenes:
        for dt in time_steps:
            for count in iterations:
                job = {"name": f"{scene} dt={dt} it={count}",
                       "bench": ["--scene", scene, "--dt", dt, "--iterations", count, *common]}
                if program is not None:
                    job["program"] = program
                built.append(job)
    return built


def merge(results):
    """One table from the jobs' results (in the jobs' order): pfx_bench's header once, then
    the rows as one pfx_bench run over the whole sweep orders them: by scene, its variant
    and engine, in the order first met, and within those in the jobs' order."""
    header = "\t".join(COLUMNS)
    rows = []
    for result in results:
        lines = result["tsv"].splitlines()
        if not lines or lines[0] != header:
            raise ValueError(f"{result.get('name', 'a job')}: pfx_bench's output does not start "
                             f"with its header line")
        rows += [line.split("\t") for line in lines[1:] if line]
    first_met = {}
    for row in rows:
        for key in ((row[0],), (row[0], row[2]), (row[0], row[2], row[1])):
            first_met.setdefault(key, len(first_met))
    rows.sort(key=lambda r: (first_met[(r[0],)], first_met[(r[0], r[2])],
                             first_met[(r[0], r[2], r[1])]))
    return "".join("\t".join(row) + "\n" for row in [list(COLUMNS), *rows])


def run(sweep_jobs, client=None):
    """Runs the jobs through pfx.sweep.run (here, or on the client's cluster) and returns the
    merged table as TSV text."""
    return merge(pfx.sweep.run(sweep_jobs, client=client))


def main(argv=None):
    import argparse

    parser = argparse.ArgumentParser(prog="python3 -m pfx.bench_sweep",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", required=True, help="scenes, comma-separated")
    parser.add_argument("--dt", required=True, help="time steps, comma-separated (1/60,...)")
    parser.add_argument("--iterations", required=True, help="iteration counts, comma-separated")
    parser.add_argument("--engine", help="engines, comma-separated (default: every one built)")
    parser.add_argument("--substeps", help="sub-step counts, comma-separated")
    parser.add_argument("--threads", help="thread counts, comma-separated")
    parser.add_argument("--seconds", type=float, help="simulated seconds of every run")
    parser.add_argument("--program", help="the pfx_bench to run")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="a dask-scheduler's address (tcp://HOST:8786)")
    where.add_argument("--local-workers", type=int,
                       help="run on a LocalCluster of this many worker processes")
    parser.add_argument("--out", help="write the table here (default: standard output)")
    options = parser.parse_args(argv)

    def split(text):
        return None if text is None else text.split(",")

    try:
        sweep_jobs = jobs(split(options.scene), split(options.dt), split(options.iterations),
                          split(options.engine), split(options.substeps), split(options.threads),
                          options.seconds, options.program)
        if options.local_workers is not None and options.local_workers < 1:
            raise ValueError(f"--local-workers: {options.local_workers} is not 1 or more")
        if options.scheduler or options.local_workers:
            from distributed import Client, LocalCluster

            if options.scheduler:
                with Client(options.scheduler) as client:
                    table = run(sweep_jobs, client)
            else:
                with LocalCluster(n_workers=options.local_workers, threads_per_worker=1) as cluster, \
                        Client(cluster) as client:
                    table = run(sweep_jobs, client)
        else:
            table = run(sweep_jobs)
    except (ValueError, RuntimeError, OSError) as error:
        print(f"pfx.bench_sweep: {error}", file=sys.stderr)
        return 2 if isinstance(error, ValueError) else 1
    if options.out:
        with open(options.out, "w", encoding="utf-8") as file:
            file.write(table)
    else:
        sys.stdout.write(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
