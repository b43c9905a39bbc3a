"""The package: the bindings under pfx, and the ROS node's message package (also named pfx)
found through it when this package comes first on the path."""
import os
import subprocess
import sys

import pfx


def test_a_message_package_named_pfx_later_on_the_path_is_reached(tmp_path):
    messages = tmp_path / "pfx" / "msg"
    messages.mkdir(parents=True)
    (tmp_path / "pfx" / "__init__.py").write_text("")
    (messages / "__init__.py").write_text("from ._Marker import *\n")
    (messages / "_Marker.py").write_text("class Marker:\n    pass\n")
    package_folder = os.path.dirname(os.path.dirname(pfx.__file__))
    path = os.pathsep.join([package_folder, str(tmp_path)])
    done = subprocess.run(
        [sys.executable, "-c", "import pfx, pfx.msg; print(pfx.World.__name__, pfx.msg.Marker.__name__)"],
        capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=path))
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["World", "Marker"]


def test_the_bindings_are_the_package_api():
    assert pfx.World is pfx._core.World
    assert "WorldBatch" in dir(pfx) and pfx.sweep.run.__doc__
