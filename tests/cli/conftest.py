"""Shared helpers for the command-line tests: where the tool is, and how to run it."""
import os
import pathlib
import subprocess

import pytest

CLI = os.environ.get("MOREAU_CLI", str(pathlib.Path(__file__).parents[2] / "build/release/moreau"))
ROOT = pathlib.Path(os.environ.get("MOREAU_ROOT", pathlib.Path(__file__).parents[2]))


def run_cli(*args, cwd=None):
    """Runs `moreau ARGS` and returns the CompletedProcess (text output)."""
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, cwd=cwd,
                          timeout=600)


@pytest.fixture
def write_scenario(tmp_path):
    def write(text, name="scenario.toml"):
        path = tmp_path / name
        path.write_text(text)
        return path
    return write
