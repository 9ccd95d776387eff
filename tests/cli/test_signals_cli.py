"""SIGINT and SIGTERM (docs/reliability.md): a time loop finishes its current step,
the completed part is published marked "interrupted" (summary, readable HDF5 trajectory), no
staging folder stays, and the exit code is 128 + the signal. A paper's case publishes nothing
and the folder keeps what it held (the other commands: test_stop_cli.py)."""
import json
import pathlib
import signal
import subprocess
import time

import h5py
import pytest

from conftest import CLI, ROOT, run_cli
from test_abm_cli import COLONY
from test_outputs_cli import hidden_leftovers
from test_particles_cli import SMALL

# 50 disks in a trap for 10^7 steps, a frame every 100.
LONG_PARTICLES = SMALL.replace("T = 1.0", "T = 100000.0") + "\n[output]\nstride = 100\n"


def cpu_seconds(pid):
    """User + system CPU time of process PID so far."""
    fields = pathlib.Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / 100.0


def start_and_signal(args, sig, ready):
    """Starts `moreau ARGS`, waits until ready() (at most 60 s, the process still running),
    sends SIG and returns (returncode, stdout, stderr) once it ended."""
    p = subprocess.Popen([CLI, *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    deadline = time.monotonic() + 60
    while not ready(p.pid):
        assert p.poll() is None, p.communicate()
        assert time.monotonic() < deadline, "the run never got ready"
        time.sleep(0.02)
    p.send_signal(sig)
    stdout, stderr = p.communicate(timeout=120)
    return p.returncode, stdout, stderr


def frames_written(parent):
    """True once a staging folder beside the output holds a trajectory and the run has computed
    for half a second (well past its first frames)."""
    return lambda pid: (any(h5.stat().st_size > 4096
                            for h5 in parent.glob(".moreau-staging.*/trajectory.h5"))
                        and cpu_seconds(pid) > 0.5)


@pytest.mark.parametrize("sig,code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_an_interrupted_particle_run_publishes_what_is_complete(tmp_path, sig, code):
    """Reproducer 2: a signal left the staging folder behind and no message."""
    scenario = tmp_path / "long.toml"
    scenario.write_text(LONG_PARTICLES)
    out = tmp_path / "out"
    rc, stdout, stderr = start_and_signal(["run", scenario, "--out", out], sig,
                                          frames_written(tmp_path))
    assert rc == code, stderr
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"moreau: interrupted by {sig.name}"), stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["termination"] == "interrupted" and summary["ok"] is False
    assert 0 < summary["steps"] < 10_000_000
    assert "failed_step" not in summary
    with h5py.File(out / "trajectory.h5", "r") as f:  # closed properly: readable
        steps = f["step"][:]
        assert steps[-1] == summary["steps"]  # the last completed step is the last frame
        assert f["positions"].shape[0] == len(steps) and len(steps) >= 2
    assert (out / "trajectory.xdmf").exists()
    assert hidden_leftovers(tmp_path) == []


def test_a_paper_case_publishes_nothing(tmp_path):
    """The paper's sliding case stops at its next step and publishes nothing: the folder keeps
    the previous result."""
    example = ROOT / "examples" / "sliding.toml"
    out = tmp_path / "out"
    assert run_cli("run", example, "--out", out, "--set", "solver.h=0.01").returncode == 0
    before = (out / "summary.json").read_bytes()
    rc, _, stderr = start_and_signal(["run", example, "--out", out, "--set", "solver.h=1e-7"],
                                     signal.SIGTERM, lambda pid: cpu_seconds(pid) > 0.5)
    assert rc == 143
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("moreau: interrupted by SIGTERM: stopped on "
                                                    "request after step"), stderr
    assert lines[0].endswith("; no result published")
    assert (out / "summary.json").read_bytes() == before
    assert hidden_leftovers(tmp_path) == []


# Two cells that neither grow nor die, for 5·10^7 steps.
WALKERS = (COLONY.replace("T = 20.0", "T = 1000000.0")
           .replace("growth_rate = 0.02", "growth_rate = 0.0")
           .replace("growth_rate = 0.04", "growth_rate = 0.0")
           .replace("death_rate = 0.01", "death_rate = 0.0") + "\n[output]\nstride = 1000\n")


def test_an_interrupted_population_run_publishes_what_is_complete(tmp_path):
    scenario = tmp_path / "colony.toml"
    scenario.write_text(WALKERS)
    out = tmp_path / "out"
    rc, _, stderr = start_and_signal(["run", scenario, "--out", out], signal.SIGTERM,
                                     frames_written(tmp_path))
    assert rc == 143, stderr
    assert stderr.strip().splitlines()[-1].startswith("moreau: interrupted by SIGTERM")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["termination"] == "interrupted"
    assert 0 < summary["engine"]["steps"] < 50_000_000
    with h5py.File(out / "trajectory.h5", "r") as f:
        assert len(f["step"]) >= 1
    assert (out / "population.csv").read_text().count("\n") >= 2
    assert hidden_leftovers(tmp_path) == []
