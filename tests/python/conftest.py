"""Shared helpers of the Python package tests: the module from the build tree (PYTHONPATH set by
ctest or `make test`), the command-line tool for bit-for-bit comparisons, the repository root."""
import os
import pathlib
import subprocess

ROOT = pathlib.Path(os.environ.get("MOREAU_ROOT", pathlib.Path(__file__).parents[2]))
CLI = os.environ.get("MOREAU_CLI", str(ROOT / "build/release/moreau"))
MOCAP = ROOT.parent / "shared" / "data" / "mocap"


def run_cli(*args):
    """Runs `moreau ARGS`; fails the test with its stderr when it does not exit 0."""
    r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    return r
