import os
import subprocess

import pytest


@pytest.fixture(scope="session")
def reference():
    """Runs pfx_python_reference with the given arguments and returns its output lines."""
    program = os.environ.get("PFX_PYTHON_REFERENCE")
    if not program:
        pytest.fail("PFX_PYTHON_REFERENCE is not set (run the tests through ctest)")

    def run(*args):
        done = subprocess.run([program, *map(str, args)], check=True, capture_output=True,
                              text=True)
        return done.stdout.splitlines()

    return run
