"""One stop mechanism for every command (docs/reliability.md, "Interrupting a run"): SIGINT or
SIGTERM stops at the next step, Newton iteration, trial or run; sweeps, studies and evaluations
publish what finished marked "interrupted", control, fill-gaps and the paper's cases publish
nothing; no staging folder or lock stays; the exit code is 128 + the signal. And a sweep's
checks before its first run: the output folder, the lock, every point of the grid, --jobs."""
import csv
import json
import pathlib
import shutil
import signal
import subprocess
import time

import pytest

from conftest import CLI, NETWORK, ROOT, SLIDING, run_cli, rejected
from test_mocap_cli import DATA
from test_outputs_cli import hidden_leftovers
from test_particles_cli import SMALL
from test_signals_cli import cpu_seconds, start_and_signal

SIGNALS = [(signal.SIGINT, 130), (signal.SIGTERM, 143)]


def staging_in(parent):
    """Ready once a staging folder exists in PARENT (the command is writing its result)."""
    return lambda pid: any(parent.glob(".moreau-staging.*"))


def busy(seconds):
    return lambda pid: cpu_seconds(pid) > seconds


def no_leftovers(*folders):
    for folder in folders:
        assert hidden_leftovers(folder) == [], folder


def last_line(stderr, sig):
    lines = stderr.strip().splitlines()
    assert lines and lines[-1].startswith(f"moreau: interrupted by {sig.name}"), stderr
    return lines[-1]


# ---------------------------------------------------------------------------------------------
# sweep

def sweep_file(tmp_path, T, seeds=4, extra=""):
    base = tmp_path / "base.toml"
    base.write_text(SMALL)
    path = tmp_path / "sweep.toml"
    path.write_text(f'command = "run"\nscenario = "base.toml"\nseeds = {seeds}\n'
                    f'run_folders = true\ncollect = ["steps"]\n{extra}\n[set]\nproblem.T = {T}\n')
    return path


def journal_hashes(out):
    path = out / "journal.jsonl"
    if not path.exists():
        return []
    return [json.loads(line)["hash"] for line in path.read_text().splitlines() if line.strip()]


def rows(out):
    with open(out / "results.csv") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("sig,code", SIGNALS)
def test_an_interrupted_sweep_journals_only_finished_runs(tmp_path, sig, code):
    """Reproducer 1: a signal during `sweep --jobs 2` exited 0 with `completed`, and every run in
    flight was journaled as finished, so the restart skipped them."""
    sweep = sweep_file(tmp_path, 300.0)
    out = tmp_path / "out"
    # Signal once a run folder is being written (a run is in flight).
    rc, _, stderr = start_and_signal(["sweep", sweep, "--jobs", 2, "--out", out], sig,
                                     lambda pid: (out / "runs").is_dir()
                                     and staging_in(out / "runs")(pid))
    assert rc == code, stderr
    last_line(stderr, sig)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["termination"] == "interrupted" and summary["ok"] is False
    table = rows(out)
    assert len(table) == 4
    journaled = journal_hashes(out)
    for row in table:
        finished = row["status"] == "completed"
        assert finished == (row["hash"] in journaled), row
        assert row["status"] in ("completed", "interrupted", "not_run"), row
    assert any(row["status"] == "interrupted" for row in table)
    no_leftovers(tmp_path, out, out / "runs")

    # The restart redoes exactly the runs not journaled.
    r = run_cli("sweep", sweep, "--jobs", 2, "--out", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["termination"] == "completed" and summary["runs_skipped"] == len(journaled)
    assert sorted(set(journal_hashes(out))) == sorted(row["hash"] for row in table)
    assert len(journal_hashes(out)) == 4  # nothing run twice
    assert all(row["status"] == "completed" for row in rows(out))
    no_leftovers(tmp_path, out, out / "runs")


def test_a_second_sweep_into_the_same_folder_is_refused(tmp_path):
    sweep = sweep_file(tmp_path, 100000.0, seeds=1)
    out = tmp_path / "out"
    first = subprocess.Popen([CLI, "sweep", sweep, "--out", out], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 60
        while not any(tmp_path.glob(".out.moreau-lock")):
            assert first.poll() is None and time.monotonic() < deadline, first.communicate()
            time.sleep(0.02)
        rejected(run_cli("sweep", sweep, "--out", out), "another moreau run", "--out")
    finally:
        first.send_signal(signal.SIGINT)
        first.communicate(timeout=120)
    assert first.returncode == 130
    no_leftovers(tmp_path, out)


@pytest.mark.parametrize("where", ["/", "file", "long"])
def test_a_sweep_checks_its_folder_before_any_run(tmp_path, where):
    """Reproducer 8: `--out /` ran every run and wrote /journal.jsonl before refusing; a file or
    an overlong path gave exit 1 with a raw filesystem error."""
    sweep = sweep_file(tmp_path, 0.05, seeds=1)
    journal_at_root = pathlib.Path("/journal.jsonl")
    had_journal = journal_at_root.exists()
    if where == "/":
        sweep.write_text(sweep.read_text().replace("run_folders = true", "run_folders = false"))
        out = "/"
    elif where == "file":
        out = tmp_path / "a_file"
        out.write_text("x")
    else:
        out = tmp_path / ("d" * 200) / ("e" * 200) / ("f" * 300)
    try:
        line = rejected(run_cli("sweep", sweep, "--out", out), "--out")
        assert "filesystem error" not in line
        assert journal_at_root.exists() == had_journal  # nothing ran, nothing was written
    finally:
        if where == "/" and not had_journal:
            journal_at_root.unlink(missing_ok=True)


def test_every_point_of_the_grid_is_checked_before_running(tmp_path):
    """A bad [set] key, or a bad later value of an axis, is one line naming the key, exit 2,
    before any run."""
    sweep = sweep_file(tmp_path, 0.05, extra="", seeds=2)
    sweep.write_text(sweep.read_text() + "problem.bogus = 1\n")
    out = tmp_path / "out"
    rejected(run_cli("sweep", sweep, "--out", out), "set.problem.bogus", "unknown key")
    assert not out.exists()
    sweep = sweep_file(tmp_path, 0.05, seeds=1, extra="[axes]\nsolver.h = [0.01, -0.01]\n")
    rejected(run_cli("sweep", sweep, "--out", out), "axes.solver.h", "run 1", "solver.h")
    assert not out.exists()


@pytest.mark.parametrize("command", ["sweep", "study"])
def test_too_many_jobs_is_one_line(tmp_path, command):
    """Reproducer 11: --jobs 1000000 ended with exit 1, "Resource temporarily unavailable"."""
    if command == "sweep":
        args = ["sweep", sweep_file(tmp_path, 0.05, seeds=1)]
    else:
        args = ["study", SLIDING, "--methods", "pbd", "--h", "0.1"]
    rejected(run_cli(*args, "--jobs", 1000000, "--out", tmp_path / "out"), "--jobs", "1024")


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="mpirun is not installed")
def test_a_bad_sweep_file_under_mpirun_says_why(tmp_path):
    """Reproducer 7: under mpirun a bad sweep file exited 1 with MPI_ABORT's banner and a
    misleading "interrupted by SIGTERM"; the error line was lost."""
    sweep = sweep_file(tmp_path, 0.05, seeds=2)
    sweep.write_text(sweep.read_text() + "problem.bogus = 1\n")
    r = subprocess.run(["mpirun", "--allow-run-as-root", "--oversubscribe", "-n", "2", CLI,
                        "sweep", sweep, "--out", tmp_path / "out"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, (r.returncode, r.stderr)
    errors = [line for line in r.stderr.splitlines() if line.startswith("moreau:")]
    assert len(errors) == 1 and "set.problem.bogus" in errors[0], r.stderr
    assert "SIGTERM" not in r.stderr


# ---------------------------------------------------------------------------------------------
# study, control, fill-gaps, evaluate-gaps, the paper's cases, particle runs

def test_an_interrupted_study_publishes_the_runs_finished(tmp_path):
    out = tmp_path / "study"
    rc, _, stderr = start_and_signal(["study", SLIDING, "--methods", "pbd", "--h",
                                      "0.1,0.01,1e-7", "--out", out], signal.SIGINT, busy(0.5))
    assert rc == 130, stderr
    last_line(stderr, signal.SIGINT)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["termination"] == "interrupted" and summary["ok"] is False
    assert "2 of 3 runs" in summary["message"]
    assert len((out / "study.csv").read_text().splitlines()) == 3  # header + 2 runs
    no_leftovers(tmp_path)


@pytest.mark.parametrize("sig,code", SIGNALS)
def test_control_stops_at_a_newton_iteration_and_publishes_nothing(tmp_path, sig, code):
    out = tmp_path / "out"
    rc, _, stderr = start_and_signal(["control", NETWORK, "--set", "discretization.steps=200000",
                                      "--out", out], sig, busy(0.5))
    assert rc == code, stderr
    assert "Newton iteration" in last_line(stderr, sig) and "no result published" in stderr
    assert not out.exists()
    no_leftovers(tmp_path)


CROWD_2S = ["--set", "problem.T=2", "--set", "output.snapshot_times=[0.0, 2.0]"]


def commands_that_write():
    """Each command at a moment its staging folder exists (writing its result, figures
    included), and whether that result is published when a signal comes then."""
    return {
        "control": (["control", NETWORK], False),
        "fill-gaps": (["fill-gaps", DATA / "Vicon.c3d", "--set", "ocp.optimal_control=false"],
                      False),
        "evaluate-gaps": (["evaluate-gaps", DATA / "Qualisys.c3d", "--gap-seconds", "0.1",
                           "--trials", 2, "--methods", "linear"], True),
        "sliding": (["run", SLIDING, "--set", "solver.h=0.01"], False),
        "particles": (["run", ROOT / "examples/crowd.toml", *CROWD_2S], True),
        "study": (["study", SLIDING, "--methods", "pbd", "--h", "0.1,0.05"], True),
    }


@pytest.mark.parametrize("name", list(commands_that_write()))
def test_a_signal_while_writing_leaves_no_staging_or_lock(tmp_path, name):
    """Reproducer 9: a signal while a command wrote its result left the staging folder and the
    lock file behind."""
    args, publishes = commands_that_write()[name]
    out = tmp_path / "out"
    rc, _, stderr = start_and_signal([*args, "--out", out], signal.SIGTERM, staging_in(tmp_path))
    assert rc == 143, stderr
    line = last_line(stderr, signal.SIGTERM)
    no_leftovers(tmp_path)
    if publishes:
        summary = json.loads((out / "summary.json").read_text())
        if summary["ok"]:  # complete when the signal came
            assert "is published" in line
        else:  # a particle run's staging folder exists while it steps
            assert summary["termination"] == "interrupted"
    else:
        assert "no result published" in line and not out.exists()


def test_a_particle_run_signalled_after_its_loop_publishes_its_complete_result(tmp_path):
    """Reproducer 9: a signal while a finished particle run drew its figures left the staging
    folder behind and published nothing."""
    out = tmp_path / "out"
    rc, _, stderr = start_and_signal(
        ["run", ROOT / "examples/crowd.toml", *CROWD_2S, "--out", out], signal.SIGINT,
        lambda pid: any(tmp_path.glob(".moreau-staging.*/summary.json")))
    assert rc == 130, stderr
    assert "the result was complete and is published" in last_line(stderr, signal.SIGINT)
    assert json.loads((out / "summary.json").read_text())["termination"] == "completed"
    no_leftovers(tmp_path)


def test_an_interrupted_evaluation_publishes_the_trials_done(tmp_path):
    out = tmp_path / "out"
    rc, _, stderr = start_and_signal(
        ["evaluate-gaps", DATA / "Qualisys.c3d", "--gap-seconds", "0.1", "--trials", 100000,
         "--methods", "linear", "--set", "evaluation.threads=1", "--out", out], signal.SIGINT,
        busy(1.0))
    assert rc == 130, stderr
    last_line(stderr, signal.SIGINT)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["termination"] == "interrupted" and summary["ok"] is False
    assert "trials" in summary["message"]
    done = len((out / "evaluation.csv").read_text().splitlines()) - 1
    assert 0 < done < 100000
    no_leftovers(tmp_path)
