"""Shared helpers for the command-line tests: where the tool is, and how to run it."""
import os
import pathlib
import subprocess

import pytest

CLI = os.environ.get("MOREAU_CLI", str(pathlib.Path(__file__).parents[2] / "build/release/moreau"))
ROOT = pathlib.Path(os.environ.get("MOREAU_ROOT", pathlib.Path(__file__).parents[2]))

# Example scenarios several test files start from.
SLIDING = ROOT / "examples/sliding.toml"
CROWD = ROOT / "examples/crowd.toml"
NETWORK = ROOT / "examples/control/network_2d.toml"
OSCILLATOR = ROOT / "examples/control/oscillator_1d.toml"


def run_cli(*args, cwd=None):
    """Runs `moreau ARGS` and returns the CompletedProcess (text output)."""
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, cwd=cwd,
                          timeout=600)


def assert_rejected(scenario, out, key, reason):
    """`moreau run SCENARIO --out OUT` must fail with exit code 2 and one stderr line naming the
    file, the key and the reason, leaving nothing in OUT."""
    r = run_cli("run", scenario, "--out", out)
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert str(scenario) in lines[0] and key in lines[0] and reason in lines[0], lines[0]
    assert not out.exists() or not any(out.iterdir())


def rejected(r, *needles):
    """A finished `moreau` run that must have exit code 2 and one stderr line holding every
    needle; returns that line."""
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])
    return lines[0]


@pytest.fixture
def write_scenario(tmp_path):
    def write(text, name="scenario.toml"):
        path = tmp_path / name
        path.write_text(text)
        return path
    return write
