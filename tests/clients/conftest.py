"""Shared helpers of the client suite: runs of the tool on shortened examples, and ParaView's
readers driven through pvbatch. Paths come from the environment (the Makefile sets them):
MOREAU_CLI (the tool), MOREAU_TESTS (the unit-test binary, which writes changing-count samples),
MOREAU_ROOT (the repository), MOREAU_CLIENTS_VENV (the virtual environment with the C3D readers
from PyPI, made by the Makefile from requirements.txt)."""
import json
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

HERE = pathlib.Path(__file__).parent
ROOT = pathlib.Path(os.environ.get("MOREAU_ROOT", HERE.parents[1]))
CLI = os.environ.get("MOREAU_CLI", str(ROOT / "build/release/moreau"))
UNIT_TESTS = os.environ.get("MOREAU_TESTS", str(ROOT / "build/release/moreau_tests"))
CLIENTS_VENV = pathlib.Path(os.environ.get("MOREAU_CLIENTS_VENV", ROOT / "build/clients-venv"))
XDMF_READERS = ("XDMFReader", "Xdmf3ReaderS", "Xdmf3ReaderT")

# The examples shortened to a few frames (the client suite checks formats, not physics).
SHORT_RUNS = {
    "crowd": ["problem.T=3", "output.snapshot_times=[0.0]", "output.vtu=true"],  # 4 frames
    "packing3d": ["problem.T=1", "output.stride=50", "output.vtu=true"],  # 100 steps, 3 frames
    "disks_1e4": ["problem.T=0.4", "output.stride=10", "output.vtu=true",
                  "output.snapshots=false"],  # 10^4 disks, 20 steps, 3 frames
}


def pvbatch():
    """The pvbatch command; the suite fails (it does not skip) when ParaView is missing, as CI
    installs it with scripts/install-deps."""
    path = shutil.which("pvbatch")
    assert path, "pvbatch not found: run scripts/install-deps (Debian packages paraview, python3-paraview)"
    return path


def paraview_read(jobs, out_dir):
    """Opens each (reader, file) of `jobs` in one pvbatch process; returns one dict of arrays per
    job (see paraview_read.py). Fails with pvbatch's stderr when it crashes."""
    out_dir.mkdir(parents=True, exist_ok=True)
    args = [pvbatch(), "--force-offscreen-rendering", str(HERE / "paraview_read.py"), str(out_dir)]
    args += [f"{reader}:{path}" for reader, path in jobs]
    r = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, f"pvbatch exit {r.returncode}:\n{r.stdout[-2000:]}\n{r.stderr[-3000:]}"
    results = []
    for k in range(len(jobs)):
        with np.load(out_dir / f"{k}.npz") as data:
            results.append({name: data[name] for name in data.files})
    return results


@pytest.fixture(scope="session")
def clients_venv():
    """The venv with the C3D readers; skips when it was not made (the Makefile makes it from
    PyPI; without network it cannot). Requested first, it skips before any work is done."""
    if not (CLIENTS_VENV / "installed").is_file():
        pytest.skip(f"{CLIENTS_VENV} not made: ezc3d and kineticstoolkit come from PyPI "
                    "(tests/clients/requirements.txt); `make test-clients` makes it when the "
                    "network is reachable")
    return CLIENTS_VENV


def c3d_read(paths, out_dir):
    """Opens each C3D file of `paths` with ezc3d and Kinetics Toolkit in one process of the
    client venv (c3d_read.py; needs the clients_venv fixture); returns one dict of arrays per
    file. Fails when a reader does."""
    out_dir.mkdir(parents=True, exist_ok=True)
    args = [str(CLIENTS_VENV / "bin" / "python"), str(HERE / "c3d_read.py"), str(out_dir)]
    r = subprocess.run(args + [str(p) for p in paths], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, \
        f"c3d_read.py exit {r.returncode}:\n{r.stdout[-2000:]}\n{r.stderr[-3000:]}"
    results = []
    for k in range(len(paths)):
        with np.load(out_dir / f"{k}.npz") as data:
            results.append({name: data[name] for name in data.files})
    return results


def run_example(name, out):
    """`moreau run examples/NAME.toml` shortened by SHORT_RUNS; returns (out, summary)."""
    args = [CLI, "run", str(ROOT / "examples" / f"{name}.toml"), "--out", str(out)]
    for setting in SHORT_RUNS[name]:
        args += ["--set", setting]
    r = subprocess.run(args, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    return out, json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="session")
def example_runs(tmp_path_factory):
    """get(name) → (name, output folder, summary) of the shortened example, run once a session."""
    runs = {}

    def get(name):
        if name not in runs:
            out, summary = run_example(name, tmp_path_factory.mktemp(name) / "out")
            runs[name] = (name, out, summary)
        return runs[name]
    return get


@pytest.fixture(scope="session", params=sorted(SHORT_RUNS))
def example_run(request, example_runs):
    """(name, output folder, summary) of one shortened example run."""
    return example_runs(request.param)
