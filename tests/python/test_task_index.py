"""One job per task, as Slurm job arrays and Kubernetes indexed Jobs run them: pfx_sim
--jobs and python3 -m pfx.sweep, each task its own process, give the results of the same
jobs run in this process; a bad task index is refused and nothing is written."""
import json
import os
import subprocess
import sys

import pytest

import pfx
import pfx.sweep
from pfx_scenes import build_arm, build_pyramid

SECONDS = 0.1  # 24 steps of the arm at 1/240 s, 6 of the pyramid at 1/60 s


def pfx_sim():
    program = os.environ.get("PFX_SIM")
    if not program:
        pytest.fail("PFX_SIM is not set (run the tests through ctest)")
    return program


@pytest.fixture
def saved_worlds(tmp_path):
    arm, _ = build_arm()
    arm.step(12)
    pyramid = build_pyramid()
    pyramid.step(3)
    paths = [str(tmp_path / "arm.pfxw"), str(tmp_path / "pyramid.pfxw")]
    arm.save(paths[0])
    pyramid.save(paths[1])
    return paths


def expected_hash(path):
    """The job run in this process: the saved world loaded and stepped as pfx_sim steps it."""
    world = pfx.World()
    world.load(path)
    world.step(round(SECONDS / world.param.time_step))
    return f"{world.state_hash():016x}", world.simulated_time


def run(args, env=None):
    return subprocess.run(args, capture_output=True, text=True,
                          env=dict(os.environ, **(env or {})))


def test_pfx_sim_tasks_equal_the_jobs_run_here(tmp_path, saved_worlds):
    jobs = tmp_path / "jobs.txt"
    jobs.write_text("# one saved world per line\n\n" + "".join(
        f"--load {path} --seconds {SECONDS} --quiet\n" for path in saved_worlds))
    results = tmp_path / "results"
    results.mkdir()
    # Task 0 by its option, task 1 as a Slurm array task would find its index.
    first = run([pfx_sim(), "--jobs", str(jobs), "--task-index", "0", "--result-dir", str(results)])
    second = run([pfx_sim(), "--jobs", str(jobs), "--result-dir", str(results)],
                 env={"SLURM_ARRAY_TASK_ID": "1"})
    assert first.returncode == 0, first.stderr
    assert second.returncode == 0, second.stderr
    hashes = []
    for task, path in enumerate(saved_worlds):
        result = json.loads((results / f"task-{task}.json").read_text())
        state_hash, time = expected_hash(path)
        assert result["task"] == task
        assert path in result["job"]
        assert result["state_hash"] == state_hash
        assert result["simulated_time"] == time
        hashes.append(result["state_hash"])
    assert hashes[0] != hashes[1]


@pytest.mark.parametrize("index, env, message", [
    (["--task-index", "2"], {}, "task index 2 (from --task-index) is out of range"),
    (["--task-index", "-1"], {}, "is negative"),
    (["--task-index", "two"], {}, "'two' (from --task-index) is not a whole number"),
    ([], {"JOB_COMPLETION_INDEX": "x1"}, "(from JOB_COMPLETION_INDEX) is not a whole number"),
    ([], {}, "no task index"),
])
def test_pfx_sim_refuses_a_bad_task_index(tmp_path, saved_worlds, index, env, message):
    jobs = tmp_path / "jobs.txt"
    jobs.write_text("".join(f"--load {path} --seconds {SECONDS}\n" for path in saved_worlds))
    clean = {variable: "" for variable in pfx.sweep.TASK_INDEX_VARIABLES}
    done = run([pfx_sim(), "--jobs", str(jobs), *index, "--result-dir", str(tmp_path)],
               env=dict(clean, **env))
    assert done.returncode == 2
    assert message in done.stderr
    assert done.stdout == ""
    assert not list(tmp_path.glob("task-*.json"))


def test_sweep_tasks_equal_the_jobs_run_here(tmp_path, saved_worlds):
    jobs = [{"name": os.path.basename(path), "world": path, "steps": 30,
             "measure": ["state_hash", "num_bodies"]} for path in saved_worlds]
    jobs_file = tmp_path / "jobs.json"
    jobs_file.write_text(json.dumps(jobs))
    here = pfx.sweep.run(jobs)
    for task, variable in enumerate(["JOB_COMPLETION_INDEX", "PFX_TASK_INDEX"]):
        out = tmp_path / f"result-{task}.json"
        done = run([sys.executable, "-m", "pfx.sweep", str(jobs_file), "--out", str(out)],
                   env={variable: str(task)})
        assert done.returncode == 0, done.stderr
        result = json.loads(out.read_text())
        assert result["task"] == task
        assert {key: result[key] for key in here[task]} == here[task]
    bad = run([sys.executable, "-m", "pfx.sweep", str(jobs_file), "--task-index", "5"])
    assert bad.returncode == 2
    assert "task index 5 (from --task-index) is out of range" in bad.stderr
