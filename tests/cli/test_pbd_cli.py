"""End-to-end tests of `moreau run` and `moreau study`: outputs, and bad input (exit code 2, one
line naming the file, the key and the reason, nothing written)."""
import csv
import json

import pytest

from conftest import ROOT, assert_rejected, run_cli

SLIDING = """
[problem]
kind = "sliding"
dimension = 3
C = 10.0
alpha = 0.19634954084936207
T = 1.0

[solver]
method = "pbd"
h = 0.01
"""

DISKS = """
[problem]
kind = "disks"
count = 6
radius = 0.2
gamma = 1.0
T = 0.5
seed = 4

[solver]
method = "pbd"
h = 0.01

[reference]
h = 0.0009765625
"""


def test_run_sliding_writes_summary_and_trajectory(tmp_path, write_scenario):
    out = tmp_path / "out"
    r = run_cli("run", write_scenario(SLIDING), "--out", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    for key in ("method", "h", "steps", "constraint_evaluations", "max_violation",
                "total_seconds", "error"):
        assert key in summary
    assert summary["method"] == "pbd"
    assert summary["steps"] == 100
    assert summary["constraint_evaluations"] == 2 * 100
    assert 0 < summary["error"] < 1.0
    with open(out / "trajectory.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["t", "x0", "x1", "x2"]
    assert len(rows) == 1 + 101
    assert not list(out.parent.glob(".moreau-staging.*"))  # staged beside, then renamed


def test_set_overrides_a_scenario_value(tmp_path, write_scenario):
    out = tmp_path / "out"
    r = run_cli("run", write_scenario(SLIDING), "--set", "solver.h=0.02", "--set",
                "solver.method=pngs", "--out", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["steps"] == 50 and summary["method"] == "pngs"


def test_run_disks_writes_particle_trajectory(tmp_path, write_scenario):
    out = tmp_path / "out"
    r = run_cli("run", write_scenario(DISKS), "--out", out)
    assert r.returncode == 0, r.stderr
    with open(out / "trajectory.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["t", "i", "x", "y"]
    assert len(rows) == 1 + 6 * 51
    summary = json.loads((out / "summary.json").read_text())
    assert summary["max_violation"] < 4 * 0.01
    assert "error" not in summary  # no reference asked for


def test_study_writes_table_orders_and_figure(tmp_path, write_scenario):
    out = tmp_path / "study"
    r = run_cli("study", write_scenario(SLIDING.replace("T = 1.0", "T = 4.0")), "--methods",
                "pbd,pngs,pgs,penalty:1000", "--h", "0.003125,0.0015625,0.00078125,0.000390625",
                "--out", out)
    assert r.returncode == 0, r.stderr
    with open(out / "study.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["method", "h", "error", "constraint_evaluations", "total_seconds"]
    assert len(rows) == 1 + 4 * 4
    summary = json.loads((out / "summary.json").read_text())
    assert abs(summary["methods"]["pbd"]["observed_order"] - 1.0) < 0.15
    assert (out / "convergence.png").stat().st_size > 10000


def test_study_of_disks_uses_a_reference(tmp_path, write_scenario):
    out = tmp_path / "study"
    r = run_cli("study", write_scenario(DISKS), "--methods", "pbd", "--h",
                "0.0625,0.03125,0.015625,0.0078125", "--out", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    errors = [run["error"] for run in summary["methods"]["pbd"]["runs"]]
    assert errors == sorted(errors, reverse=True)  # smaller h, smaller error


BAD_INPUTS = [
    ("unknown key", SLIDING + "\nflux = 3\n", "solver.flux", "unknown key"),
    ("wrong type", SLIDING.replace("C = 10.0", 'C = "ten"'), "problem.C", "expected a number"),
    ("h zero", SLIDING.replace("h = 0.01", "h = 0.0"), "solver.h", "must be > 0"),
    ("h negative", SLIDING.replace("h = 0.01", "h = -0.1"), "solver.h", "must be > 0"),
    ("T/h not whole", SLIDING.replace("h = 0.01", "h = 0.3"), "solver.h", "whole number"),
    ("radius", DISKS.replace("radius = 0.2", "radius = -0.2"), "problem.radius", "must be > 0"),
    ("radius zero", DISKS.replace("radius = 0.2", "radius = 0"), "problem.radius", "must be > 0"),
    ("dimension", SLIDING.replace("dimension = 3", "dimension = 2"), "problem.dimension",
     "must be in [3"),
    ("kind", SLIDING.replace('"sliding"', '"spheres"'), "problem.kind", "unknown kind"),
    ("method", SLIDING.replace('"pbd"', '"rk4"'), "solver.method", "must be one of pbd, pngs, pgs, penalty"),
    ("infeasible", DISKS.replace("count = 6", "count = 2") +
     "\n", "problem.positions", "overlap"),
    ("bad toml", "[problem\nkind=", "line", ""),
]


@pytest.mark.parametrize("name,text,key,reason", BAD_INPUTS, ids=[b[0] for b in BAD_INPUTS])
def test_bad_input_is_one_line_exit_2_and_writes_nothing(tmp_path, write_scenario, name, text,
                                                         key, reason):
    if name == "infeasible":
        # Two disks given overlapping positions.
        text = text.replace("[solver]", "positions = [[0.0, 0.0], [0.1, 0.0]]\n\n[solver]")
    assert_rejected(write_scenario(text), tmp_path / "out", key, reason)


def test_unreadable_file_is_exit_2(tmp_path):
    r = run_cli("run", tmp_path / "missing.toml", "--out", tmp_path / "out")
    assert r.returncode == 2
    assert "missing.toml" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_study_bad_method_is_exit_2(tmp_path, write_scenario):
    r = run_cli("study", write_scenario(SLIDING), "--methods", "pbd,euler", "--h", "0.1",
                "--out", tmp_path / "out")
    assert r.returncode == 2
    assert "--methods" in r.stderr and "euler" in r.stderr


def test_examples_parse(tmp_path):
    # Every shipped PBD example is valid (a few steps of each).
    for name in ("sliding.toml", "sliding_d5.toml", "disks.toml"):
        r = run_cli("run", ROOT / "examples" / name, "--set", "problem.T=0.01", "--set",
                    "solver.h=0.001", "--out", tmp_path / name)
        assert r.returncode == 0, (name, r.stderr)
