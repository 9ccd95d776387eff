"""Validation, messages and summaries (docs/reliability.md): unknown keys in arrays of
tables, booleans, the room's geometry, a directory as scenario file, a start that cannot be made
feasible; messages that name each key once as the user writes it; summaries that give null and a
reason, never a number, for what failed."""
import json

import pytest

from conftest import CROWD, NETWORK, OSCILLATOR, ROOT, SLIDING, rejected, run_cli


BOX = """
[problem]
kind = "particles"
dimension = 2
count = 4
radius = 0.5
T = 0.1
seed = 2

[domain]
lo = [0.0, 0.0]
hi = [10.0, 10.0]

[solver]
h = 0.01
"""


@pytest.mark.parametrize("table, entry, key, suggestion", [
    ("walls", "normal = [0.0, 1.0]\noffset = 0.0", "ofset", "offset"),
    ("spheres", "center = [5.0, 5.0]\nradius = 1.0", "raduis", "radius"),
    ("segments", "a = [1.0, 1.0]\nb = [2.0, 1.0]", "colour", None),
])
def test_unknown_keys_in_arrays_of_tables_are_errors(tmp_path, write_scenario, table, entry, key,
                                                     suggestion):
    scenario = write_scenario(BOX + f"\n[[{table}]]\n{entry}\n{key} = 5.0\n")
    out = tmp_path / "out"
    line = rejected(run_cli("run", scenario, "--out", out), f"{table}[0].{key}: unknown key")
    if suggestion:
        assert f"(did you mean {suggestion}?)" in line
    assert not out.exists()


def test_a_misspelt_top_level_key_gets_a_suggestion(tmp_path):
    rejected(run_cli("run", CROWD, "--out", tmp_path / "out", "--set", "solver.hh=0.1"),
             "solver.hh: unknown key (did you mean solver.h?)")


@pytest.mark.parametrize("args, key", [
    (["run", CROWD, "--set", "domain.periodic=[1, 0]"], "domain.periodic"),
    (["run", CROWD, "--set", "output.hdf5=1"], "output.hdf5"),
    (["control", NETWORK, "--set",
      "network.nodes=[{fixed = 1, position = [0.0, 0.0]}, {mass = 1.0, position = [1.0, 0.0]},"
      " {mass = 1.0, position = [0.5, -0.8]}]"], "network.nodes[0].fixed"),
])
def test_integers_are_not_booleans(tmp_path, args, key):
    rejected(run_cli(*args, "--out", tmp_path / "out"), key, "true or false")


def test_the_crowd_must_start_inside_the_room(tmp_path):
    rejected(run_cli("run", CROWD, "--out", tmp_path / "a", "--set", "domain.lo=[-5.0, -5.0]"),
             "domain.lo", "start box [-5, 14.5] × [-5, 14.5] is outside the room [0, 15] × [0, 15]")
    rejected(run_cli("run", CROWD, "--out", tmp_path / "b", "--set", "initial.hi=[16.0, 10.0]"),
             "initial.lo", "outside the room")


def test_the_door_must_fit_in_its_wall(tmp_path):
    line = rejected(run_cli("run", CROWD, "--out", tmp_path / "out", "--set",
                            "room.door_width=20.0"), "room.door_width")
    assert "room: room." not in line


def test_a_directory_as_scenario_file_is_named_so(tmp_path):
    rejected(run_cli("run", ROOT / "examples", "--out", tmp_path / "out"), "is a directory")


def test_a_start_that_cannot_be_made_feasible_names_initial_positions(tmp_path, write_scenario):
    # Four disks of radius 0.5 in a walled 1 × 1 box: no projection can separate them.
    scenario = write_scenario(BOX.replace("hi = [10.0, 10.0]", "hi = [1.0, 1.0]\nbox_walls = true")
                              + "\n[initial]\npositions = [[0.5, 0.5], [0.5, 0.5], [0.5, 0.5],"
                                " [0.5, 0.5]]\n")
    r = run_cli("run", scenario, "--out", tmp_path / "out", "--fix-overlaps")
    rejected(r, "initial.positions", "cannot be made feasible")


def test_library_checks_name_the_scenario_key(tmp_path):
    line = rejected(run_cli("run", CROWD, "--out", tmp_path / "out", "--set",
                            "forces.trap_gamma=-1"), "forces.trap_gamma", "(got -1)")
    assert "trap.gamma" not in line


def test_a_spring_node_index_is_shown_as_written(tmp_path):
    line = rejected(run_cli("control", NETWORK, "--out", tmp_path / "out", "--set",
                            "network.springs=[{nodes = [0, 1e300], stiffness = 5.0, damping = 1.0,"
                            " rest_min = 0.7, rest_max = 1.3}]"),
                    "network.springs[0].nodes", "node index 1e+300 is out of range [0, 3)")
    assert "-2147483648" not in line


def test_each_key_is_named_once(tmp_path):
    line = rejected(run_cli("run", CROWD, "--out", tmp_path / "out", "--set", "solver.order=foo"),
                    "solver.order")
    assert line.count("solver.order") == 1
    assert line.count(str(CROWD)) == 1


def test_a_diverged_penalty_run_fails_with_a_null_error(tmp_path):
    out = tmp_path / "out"
    r = run_cli("run", SLIDING, "--out", out, "--set", "solver.method=penalty", "--set",
                "solver.penalty=1e300", "--set", "problem.T=1")
    assert r.returncode == 3, r.stderr
    assert "diverged" in r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["ok"] is False
    assert summary["termination"] == "diverged"
    assert summary["error"] is None
    assert "diverged" in summary["message"]


def test_a_failed_control_solve_reports_no_value(tmp_path):
    out = tmp_path / "out"
    r = run_cli("control", OSCILLATOR, "--out", out, "--set", "newton.max_iterations=1")
    assert r.returncode == 3, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["ok"] is False
    assert summary["message"]
    assert summary["value"] is None
    assert summary["tracking_rms"] is None
    assert summary["residual_norm"] > 0.0
