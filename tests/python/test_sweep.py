"""pfx.sweep: jobs run here and on a LocalCluster of two worker processes give the same
results, bit for bit; bad jobs and bad task indices raise before anything runs."""
import os
import re

import numpy as np
import pytest

import pfx
import pfx.sweep
from pfx_scenes import ARM_URDF, build_arm

ARM_JOB = {"urdf": ARM_URDF, "urdf_param": {"fixed_base": True}, "ground": True,
           "world_param": {"enable_sleep": False}, "steps": 40}


def tiny_jobs(saved_path):
    arm, _ = build_arm()
    arm.step(10)
    arm.save(saved_path)
    measures = ["state_hash", "simulated_time", "positions"]
    return [
        dict(ARM_JOB, name="shoulder 0.4", joint_targets={"joint_2": 0.4},
             measure=measures + ["joint_positions"]),
        dict(ARM_JOB, name="shoulder 1.2", joint_targets={"joint_2": 1.2},
             measure=measures + ["joint_positions"]),
        {"name": "saved bytes", "world": arm.to_bytes(), "steps": 30, "measure": measures},
        {"name": "saved file", "world": saved_path, "steps": 30, "measure": measures},
    ]


def same_results(a, b):
    assert [r.keys() for r in a] == [r.keys() for r in b]
    for x, y in zip(a, b):
        for key in x:
            if isinstance(x[key], np.ndarray):
                assert x[key].tobytes() == y[key].tobytes(), key
            else:
                assert x[key] == y[key], key


def test_local_cluster_of_two_processes_equals_the_local_run(tmp_path):
    distributed = pytest.importorskip("distributed")
    jobs = tiny_jobs(str(tmp_path / "arm.pfxw"))
    local = pfx.sweep.run(jobs)
    # The two arm jobs drive the shoulder to different angles: their results must differ.
    assert local[0]["state_hash"] != local[1]["state_hash"]
    assert abs(local[0]["joint_positions"][1] - local[1]["joint_positions"][1]) > 0.01
    # The saved world as bytes or as a file is the same world.
    assert local[2]["state_hash"] == local[3]["state_hash"]

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote = pfx.sweep.run(jobs, client=client)
        pids = set(client.run(os.getpid).values())
    assert len(pids) == 2 and os.getpid() not in pids
    same_results(local, remote)


def test_table_holds_the_scalar_measures(tmp_path):
    results = pfx.sweep.run(tiny_jobs(str(tmp_path / "arm.pfxw"))[2:])
    table = pfx.sweep.table(results)
    assert table.dtype.names == ("name", "steps", "state_hash", "simulated_time")
    assert list(table.name) == ["saved bytes", "saved file"]
    assert list(table.state_hash) == [r["state_hash"] for r in results]


@pytest.mark.parametrize("job, message", [
    ({"steps": 1}, "either 'world'"),
    (dict(ARM_JOB, steps=-1), "'steps' must be a whole number"),
    (dict(ARM_JOB, steps=1.5), "'steps' must be a whole number"),
    (dict(ARM_JOB, measure=["speed"]), "unknown measure 'speed'"),
    (dict(ARM_JOB, colour="red"), "unknown field 'colour'"),
    ({"world": b"x", "steps": 1, "ground": True}, "'ground' goes with 'urdf'"),
    ({"world": b"x", "steps": 1, "measure": ["joint_positions"]}, "needs a job with 'urdf'"),
])
def test_a_bad_job_raises_before_any_job_runs(job, message):
    # Job 0 would fail when run (no such file): the error is job 1's, so nothing ran.
    missing = {"world": "/nonexistent/world.pfxw", "steps": 1}
    with pytest.raises(ValueError, match="job 1: .*" + re.escape(message)):
        pfx.sweep.run([missing, job])


def test_task_index_comes_from_the_option_then_the_environment():
    resolve = pfx.sweep.resolve_task_index
    environ = {"SLURM_ARRAY_TASK_ID": "1", "JOB_COMPLETION_INDEX": "2"}
    assert resolve(None, 3, environ) == 1
    assert resolve(None, 3, {"JOB_COMPLETION_INDEX": "2"}) == 2
    assert resolve(None, 3, dict(environ, PFX_TASK_INDEX="0")) == 0
    assert resolve("2", 3, environ) == 2
    for given, message in [("3", "out of range: the job list has 3 jobs"), ("-1", "negative"),
                           ("one", "not a whole number"), ("1.0", "not a whole number"),
                           ("", "not a whole number")]:
        with pytest.raises(ValueError, match=message):
            resolve(given, 3, {})
    with pytest.raises(ValueError, match="no task index"):
        resolve(None, 3, {})
