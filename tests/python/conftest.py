# pytest set-up for the Python module: ctest sets PYTHONPATH to build/python and
# MCREF_BINARY, MCREF_SOURCE_DIR (CMakeLists.txt, test python.pytest).
import os
import subprocess

import pytest

SOURCE_DIR = os.environ.get("MCREF_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
BINARY = os.environ.get("MCREF_BINARY", os.path.join(SOURCE_DIR, "build", "mcref"))


@pytest.fixture
def cli():
    """Runs the mcref executable; returns (exit code, stdout, stderr)."""
    def run(*args):
        p = subprocess.run([BINARY, *args], capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr
    return run


@pytest.fixture
def source_dir():
    return SOURCE_DIR
