# Shared fixtures of the Python module's tests (registered in CTest by tests/CMakeLists.txt,
# which sets PYTHONPATH to build/python and the variables read here).
import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("PENUMBRA_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
CORNELL = SOURCE_DIR / "scenes" / "cornell.json"


@pytest.fixture
def cli():
    """Runs the penumbra program; returns the CompletedProcess (text, stdout and stderr captured)."""
    exe = os.environ.get("PENUMBRA_EXECUTABLE", str(SOURCE_DIR / "build" / "penumbra"))

    def run(*args):
        return subprocess.run([exe, *map(str, args)], capture_output=True, text=True, timeout=600)

    return run


@pytest.fixture
def cornell():
    return CORNELL
