"""After `source devel/setup.bash`, whose package pfx holds the ROS node's messages and
services, `import pfx` gives the module, and pfx.msg and pfx.srv still import."""
import os
import subprocess
import sys

import pytest

SCRIPT = """
import pfx, pfx.msg, pfx.srv
world = pfx.World(pfx.WorldParam(gravity=(0, 0, -9.80665)))
ball = world.add_body(pfx.Shape.sphere(0.1), pfx.BodyInit(position=(0, 0, 1)))
world.step(30)
print(pfx.World.__module__, pfx.srv.Raycast.__name__, pfx.msg.Contact.__name__,
      float(world.positions[ball, 2]) < 1)
"""


def test_the_module_and_the_messages_import_after_sourcing_setup_bash():
    setup = os.environ.get("PFX_DEVEL_SETUP")
    if not setup:
        pytest.fail("PFX_DEVEL_SETUP is not set (run the tests through ctest)")
    # Only what sourcing puts on the path: the test's own PYTHONPATH (the module's folder) goes.
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    done = subprocess.run(["bash", "-c", 'source "$1" && exec "$2" -c "$3"', "bash", setup,
                           sys.executable, SCRIPT], capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["pfx._core", "Raycast", "Contact", "True"]
