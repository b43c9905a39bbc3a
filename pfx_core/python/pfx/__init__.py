"""pfx: real-time rigid-body physics (after Sony's Physics Effects).

Build a World, add bodies (add_body, load_urdf, load_scene, load_octomap), step it and
read its states as numpy arrays. Vectors are 3 numbers, quaternions 4 as (x, y, z, w).
A call that pfx rejects raises pfx.Error with pfx's message and changes nothing.

Characters that walk, climb steps and jump: CharacterController. Many worlds in one
process: WorldBatch. Many jobs across processes or machines (a Dask cluster, or one job per
task of a Slurm array or Kubernetes indexed Job): pfx.sweep; pfx_bench's sweeps run that
way through pfx.bench_sweep.
"""
import os as _os
import sys as _sys

from pfx._core import *  # noqa: F401,F403 -- the bindings are the package's API
from pfx._core import __doc__ as _core_doc  # noqa: F401


def _message_package_folders():
    """Other folders named pfx on the path that hold the ROS node's messages or services
    (the catkin package is named pfx too): `import pfx.msg` then finds them, whichever of
    the two comes first on the path."""
    own = _os.path.realpath(_os.path.dirname(__file__))
    for entry in _sys.path:
        folder = _os.path.realpath(_os.path.join(entry or _os.curdir, "pfx"))
        if folder == own:
            continue
        if any(_os.path.isfile(_os.path.join(folder, sub, "__init__.py")) for sub in ("msg", "srv")):
            yield folder


__path__ = list(__path__) + [f for f in _message_package_folders() if f not in __path__]


def __getattr__(name):
    # pfx.sweep on first use, so that `python3 -m pfx.sweep` runs it without a second copy.
    if name == "sweep":
        import importlib

        return importlib.import_module("pfx.sweep")
    raise AttributeError(f"module 'pfx' has no attribute {name!r}")
