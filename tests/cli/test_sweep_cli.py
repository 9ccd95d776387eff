"""`moreau sweep`: the same table whatever the number of MPI ranks or threads, restart after a
kill, failing runs as rows, bad sweep files rejected."""
import csv
import json
import shutil
import signal
import subprocess
import time

import pytest

from conftest import CLI, ROOT, run_cli
from test_pbd_cli import DISKS  # the paper's disks case, small

FAILED = 3  # the exit code of a sweep whose table has failed runs
MPIRUN = shutil.which("mpirun")
needs_mpirun = pytest.mark.skipif(MPIRUN is None,
                                  reason="mpirun is absent (Debian: openmpi-bin): MPI not tested")

BASE = """
[problem]
kind = "particles"
dimension = 2
count = 12
radius = 0.2
T = {T}
seed = 1
[room]
width = 4.0
height = 4.0
door_width = 1.0
[domain]
lo = [0.3, 0.3]
hi = [3.7, 3.7]
[forces]
propulsion_speed = 1.5
diffusion = 0.01
[solver]
h = 0.01
"""

# 2 door widths × 3 radii (one too large to place 12 people in the room, which only the run's
# set-up finds: 4 failed rows) × 2 seeds = 12 runs; with failed runs the sweep writes its table
# and exits 3.
SWEEP = """
command = "run"
scenario = "base.toml"
seeds = 2
collect = ["evacuated", "evacuation_time", "msd", "positions_hash", "steps", "settings.room.door_width"]
[axes]
room.door_width = [0.8, 1.6]
problem.radius = [0.2, 0.15, 1.5]
"""


@pytest.fixture
def sweep_file(tmp_path):
    def write(T=1.0, sweep=SWEEP):
        (tmp_path / "base.toml").write_text(BASE.format(T=T))
        path = tmp_path / "sweep.toml"
        path.write_text(sweep)
        return path
    return write


def mpi_sweep(ranks, *args):
    return subprocess.run([MPIRUN, "--allow-run-as-root", "--oversubscribe", "-n", str(ranks), CLI,
                           "sweep", *map(str, args)], capture_output=True, text=True, timeout=600)


def rows(out):
    with open(out / "results.csv", newline="") as f:
        return list(csv.DictReader(f))


def test_table_has_one_row_per_run_in_grid_order_with_failed_runs_reported(sweep_file, tmp_path):
    out = tmp_path / "out"
    r = run_cli("sweep", sweep_file(), "--out", out)
    assert r.returncode == FAILED, r.stderr
    table = rows(out)
    assert [int(row["run"]) for row in table] == list(range(12))
    assert len({row["hash"] for row in table}) == 12
    expected = [(w, v, s) for w in ("0.8", "1.6") for v in ("0.2", "0.15", "1.5") for s in ("1", "2")]
    assert [(row["room.door_width"], row["problem.radius"], row["problem.seed"])
            for row in table] == expected
    failed = [row for row in table if row["problem.radius"] == "1.5"]
    assert len(failed) == 4
    for row in failed:  # the failing runs are rows with their status and message
        assert row["status"] == "input_error"
        assert "could not place" in row["message"] and row["evacuated"] == ""
    for row in table:
        if row not in failed:
            assert row["status"] == "completed" and row["message"] == ""
            assert 0 <= int(row["evacuated"]) <= 12 and float(row["msd"]) > 0
            assert int(row["steps"]) == 100
            assert row["settings.room.door_width"] == row["room.door_width"]  # dotted keys
    assert r.stderr.count("input_error") == 4  # each failure named on stderr as it happens
    assert "4 of 12 runs failed" in r.stderr.strip().splitlines()[-1]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["runs"] == 12 and summary["runs_failed"] == 4 and summary["runs_skipped"] == 0
    assert (out / "results.h5").stat().st_size > 0
    assert not (out / "runs").exists()  # per-run folders only on request


def test_threads_give_the_same_bytes(sweep_file, tmp_path):
    sweep = sweep_file()
    one, two = tmp_path / "one", tmp_path / "two"
    assert run_cli("sweep", sweep, "--out", one).returncode == FAILED
    assert run_cli("sweep", sweep, "--out", two, "--jobs", "3").returncode == FAILED
    for name in ("results.csv", "results.h5"):
        assert (one / name).read_bytes() == (two / name).read_bytes(), name


@needs_mpirun
def test_one_two_three_ranks_and_no_mpi_give_the_same_bytes(sweep_file, tmp_path):
    sweep = sweep_file()
    plain = tmp_path / "plain"
    assert run_cli("sweep", sweep, "--out", plain).returncode == FAILED
    for ranks in (1, 2, 3):
        out = tmp_path / f"ranks{ranks}"
        r = mpi_sweep(ranks, sweep, "--out", out)
        assert r.returncode == FAILED, r.stderr
        assert json.loads((out / "summary.json").read_text())["ranks"] == ranks
        for name in ("results.csv", "results.h5"):
            assert (out / name).read_bytes() == (plain / name).read_bytes(), (ranks, name)


def test_killed_sweep_restarts_where_it_stopped_and_ends_with_the_same_table(sweep_file,
                                                                             tmp_path):
    sweep = sweep_file(T=4.0)
    reference = tmp_path / "reference"
    assert run_cli("sweep", sweep, "--out", reference).returncode == FAILED
    out = tmp_path / "killed"
    journal = out / "journal.jsonl"
    p = subprocess.Popen([CLI, "sweep", str(sweep), "--out", str(out)],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and p.poll() is None:
        if journal.exists() and journal.read_text().count("\n") >= 5:
            break
        time.sleep(0.005)
    p.send_signal(signal.SIGKILL)
    p.wait()
    finished = journal.read_text().count("\n")
    assert 5 <= finished < 12, finished  # killed mid-way
    assert not (out / "results.csv").exists()
    if MPIRUN is not None:  # the rest on two ranks
        r = mpi_sweep(2, sweep, "--out", out)
    else:
        r = run_cli("sweep", sweep, "--out", out)
    assert r.returncode == FAILED, r.stderr  # the failed runs of the journal count too
    summary = json.loads((out / "summary.json").read_text())
    assert summary["runs_skipped"] == finished
    assert (out / "results.csv").read_bytes() == (reference / "results.csv").read_bytes()
    again = run_cli("sweep", sweep, "--out", out)  # nothing left to run
    assert again.returncode == FAILED
    assert json.loads((out / "summary.json").read_text())["runs_skipped"] == 12


def test_run_folders_on_request(sweep_file, tmp_path):
    sweep = sweep_file(sweep=SWEEP + "\n".join(["", "[set]", "problem.count = 8"]) + "\n")
    sweep.write_text('run_folders = true\n' + sweep.read_text())
    out = tmp_path / "out"
    assert run_cli("sweep", sweep, "--out", out).returncode == FAILED
    for row in rows(out):
        summary = out / "runs" / row["hash"] / "summary.json"
        assert summary.exists() == (row["status"] == "completed"), row
        if summary.exists():
            assert json.loads(summary.read_text())["particles"] == 8


@pytest.mark.parametrize("text, key, reason", [
    ('command = "run"\nscenario = "base.toml"\ncombine = "zip"\n[axes]\na.b = [1, 2]\nc = [1]\n',
     "axes", "same number of values"),
    ('command = "walk"\nscenario = "base.toml"\n', "command", "unknown command"),
    ('command = "run"\nscenario = "missing.toml"\n', "scenario", "cannot read"),
    ('command = "run"\nscenario = "base.toml"\nseeds = 0\n', "seeds", "≥ 1"),
    ('command = "run"\nscenario = "base.toml"\nsed = 3\n', "sed", "unknown key"),
])
def test_bad_sweep_file_is_rejected_before_anything_is_written(sweep_file, tmp_path, text, key,
                                                               reason):
    sweep = sweep_file(sweep=text)
    out = tmp_path / "out"
    r = run_cli("sweep", sweep, "--out", out)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and str(sweep) in lines[0] and key in lines[0] and reason in lines[0], \
        r.stderr
    assert not out.exists()


def test_control_and_paper_case_sweeps(tmp_path):
    control = tmp_path / "control.toml"
    control.write_text(f'command = "control"\nscenario = "{ROOT}/examples/control/oscillator_1d.toml"\n'
                       'collect = ["value", "steps"]\n[axes]\ndiscretization.steps = [100, 200]\n')
    r = run_cli("sweep", control, "--out", tmp_path / "control")
    assert r.returncode == 0, r.stderr
    table = rows(tmp_path / "control")
    assert [row["status"] for row in table] == ["converged"] * 2
    assert [row["steps"] for row in table] == ["100", "200"]
    sliding = tmp_path / "sliding.toml"
    sliding.write_text(f'command = "run"\nscenario = "{ROOT}/examples/sliding.toml"\n'
                       'collect = ["error"]\n[axes]\nsolver.h = [0.01, 0.005]\n')
    r = run_cli("sweep", sliding, "--out", tmp_path / "sliding")
    assert r.returncode == 0, r.stderr
    errors = [float(row["error"]) for row in rows(tmp_path / "sliding")]
    assert 0 < errors[1] < errors[0]  # PBD converges as h shrinks


def study_rows_without_timings(out):
    """study.csv without its last column (total_seconds: the run's wall time differs every time)."""
    with open(out / "study.csv", newline="") as f:
        table = list(csv.reader(f))
    assert table[0][-1] == "total_seconds"
    return [row[:-1] for row in table]


@needs_mpirun
def test_study_on_two_ranks_and_two_threads_gives_the_same_table_as_one_process(tmp_path):
    scenario = tmp_path / "disks.toml"
    scenario.write_text(DISKS)  # a reference solution: every rank computes the same one
    study = ["study", str(scenario), "--methods", "pbd,pngs,penalty:1000", "--h",
             "0.0625,0.03125,0.015625"]
    plain = tmp_path / "plain"
    assert run_cli(*study, "--out", plain).returncode == 0
    threads = tmp_path / "threads"
    assert run_cli(*study, "--jobs", "2", "--out", threads).returncode == 0
    ranks = tmp_path / "ranks"
    r = subprocess.run([MPIRUN, "--allow-run-as-root", "--oversubscribe", "-n", "2", CLI, *study,
                        "--out", str(ranks)], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    expected = study_rows_without_timings(plain)
    assert len(expected) == 1 + 3 * 3
    assert study_rows_without_timings(threads) == expected
    assert study_rows_without_timings(ranks) == expected
    # One copy wrote the report (rank 0), and it found the same observed orders.
    assert r.stdout.count("wrote ") == 1
    orders = [json.loads((d / "summary.json").read_text())["methods"]["pbd"]["observed_order"]
              for d in (plain, ranks)]
    assert orders[0] == orders[1]
