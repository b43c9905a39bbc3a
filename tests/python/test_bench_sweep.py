"""pfx.bench_sweep: pfx_bench's sweep over scenes, time steps and iterations split into
pfx.sweep jobs gives the table one pfx_bench run writes, here and on a LocalCluster of two
worker processes (all but the wall-time column, which no two runs share), and one of its
jobs runs as a job array's task; bad sweeps raise before anything runs."""
import json
import os
import subprocess
import sys

import pytest

import pfx.bench_sweep
import pfx.sweep

SCENES = ["chain", "spinner"]
TIME_STEPS = ["1/60", "1/120"]
ITERATIONS = [4, 8]
SECONDS = 0.1


def bench_program():
    program = os.environ.get("PFX_BENCH")
    if not program:
        pytest.fail("PFX_BENCH is not set (run the tests through ctest)")
    return program


def without_wall_time(table):
    rows = [line.split("\t") for line in table.splitlines()]
    assert all(len(row) == len(pfx.bench_sweep.COLUMNS) for row in rows)
    for row in rows:
        del row[pfx.bench_sweep.WALL_TIME_COLUMN]
    return rows


def one_pfx_bench_run():
    done = subprocess.run(
        [bench_program(), "--scene", ",".join(SCENES), "--engine", "pfx",
         "--dt", ",".join(TIME_STEPS), "--iterations", ",".join(map(str, ITERATIONS)),
         "--seconds", str(SECONDS)], check=True, capture_output=True, text=True)
    return done.stdout


def test_a_sweep_on_two_worker_processes_gives_the_table_of_one_pfx_bench_run():
    distributed = pytest.importorskip("distributed")
    jobs = pfx.bench_sweep.jobs(SCENES, TIME_STEPS, ITERATIONS, engines=["pfx"],
                                seconds=SECONDS, program=bench_program())
    assert len(jobs) == len(SCENES) * len(TIME_STEPS) * len(ITERATIONS)
    local = pfx.bench_sweep.run(jobs)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote = pfx.bench_sweep.run(jobs, client=client)
        assert len(set(client.run(os.getpid).values()) - {os.getpid()}) == 2
    expected = without_wall_time(one_pfx_bench_run())
    assert without_wall_time(local) == expected
    assert without_wall_time(remote) == expected
    # Every scene, time step and iteration count has its rows, and the errors differ
    # between time steps (the table is not one run repeated).
    rows = expected[1:]
    assert {(r[0], r[5]) for r in rows} == {(s, str(it)) for s in SCENES for it in ITERATIONS}
    assert all(len({r[3] for r in rows if r[0] == s}) == len(TIME_STEPS) for s in SCENES)
    by_step = {}
    for r in rows:
        by_step.setdefault((r[0], r[2], r[5], r[7]), set()).add(r[8])
    assert any(len(values) == len(TIME_STEPS) for values in by_step.values())


def test_the_command_line_writes_the_table_and_refuses_a_bad_sweep(tmp_path):
    out = tmp_path / "results.tsv"
    env = dict(os.environ, PFX_BENCH=bench_program())
    done = subprocess.run(
        [sys.executable, "-m", "pfx.bench_sweep", "--scene", "spinner", "--engine", "pfx",
         "--dt", "1/60", "--iterations", "4", "--seconds", str(SECONDS), "--out", str(out)],
        capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr
    table = out.read_text()
    assert table.splitlines()[0] == "\t".join(pfx.bench_sweep.COLUMNS)
    assert len(table.splitlines()) > 1 and all(
        line.startswith("spinner\tpfx\t") for line in table.splitlines()[1:])

    bad = tmp_path / "bad.tsv"
    for args, says in ((["--dt", "0", "--iterations", "4"], "time step '0'"),
                       (["--dt", "1/60", "--iterations", "-3"], "iterations: '-3'"),
                       (["--dt", "abc", "--iterations", "4"], "time step 'abc'")):
        done = subprocess.run([sys.executable, "-m", "pfx.bench_sweep", "--scene", "spinner",
                               *args, "--out", str(bad)], capture_output=True, text=True, env=env)
        assert done.returncode == 2 and says in done.stderr, done.stderr
        assert not bad.exists()
    # A scene pfx_bench does not know: its run fails, with pfx_bench's message, and the
    # table is not written.
    done = subprocess.run([sys.executable, "-m", "pfx.bench_sweep", "--scene", "nosuchscene",
                           "--dt", "1/60", "--iterations", "4", "--out", str(bad)],
                          capture_output=True, text=True, env=env)
    assert done.returncode == 1 and "unknown scene 'nosuchscene'" in done.stderr, done.stderr
    assert not bad.exists()


def test_a_bench_job_runs_as_an_indexed_task(tmp_path):
    jobs = pfx.bench_sweep.jobs(["spinner"], ["1/60", "1/120"], [4], engines=["pfx"],
                                seconds=SECONDS, program=bench_program())
    listed = tmp_path / "jobs.json"
    listed.write_text(json.dumps(jobs))
    done = subprocess.run([sys.executable, "-m", "pfx.sweep", str(listed)], capture_output=True,
                          text=True, env=dict(os.environ, SLURM_ARRAY_TASK_ID="1"))
    assert done.returncode == 0, done.stderr
    task = json.loads(done.stdout)
    assert task["task"] == 1 and task["job"] == jobs[1]
    assert without_wall_time(task["tsv"]) == without_wall_time(pfx.sweep.run_job(jobs[1])["tsv"])
    assert without_wall_time(task["tsv"]) != without_wall_time(pfx.sweep.run_job(jobs[0])["tsv"])


def test_bad_sweeps_and_bench_jobs_raise_before_anything_runs():
    with pytest.raises(ValueError, match="scenes: no value given"):
        pfx.bench_sweep.jobs([], ["1/60"], [4])
    with pytest.raises(ValueError, match="scene 'a,b'"):
        pfx.bench_sweep.jobs(["a,b"], ["1/60"], [4])
    with pytest.raises(ValueError, match="time step 'nan'"):
        pfx.bench_sweep.jobs(["chain"], ["nan"], [4])
    with pytest.raises(ValueError, match="iterations: 0"):
        pfx.bench_sweep.jobs(["chain"], ["1/60"], [0])
    with pytest.raises(ValueError, match="seconds"):
        pfx.bench_sweep.jobs(["chain"], ["1/60"], [4], seconds=-1)
    good = {"bench": ["--scene", "chain"], "program": bench_program()}
    for bad, says in (({"bench": "--scene chain"}, "'bench' must be a list"),
                      ({"bench": ["--dt", 60]}, "'bench' must be a list"),
                      ({"bench": [], "steps": 3}, "unknown field 'steps'"),
                      ({"bench": [], "program": 3}, "'program' is a int")):
        with pytest.raises(ValueError, match=f"job 1: {says}"):
            pfx.sweep.run([good, bad])
