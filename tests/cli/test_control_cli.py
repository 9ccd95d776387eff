"""End-to-end tests of `moreau control` (docs/control.md): outputs, the study, and bad input.

The CLI is found through MOREAU_CLI, the repository through MOREAU_ROOT.
"""
import csv
import json
import os
import pathlib
import re
import subprocess

import pytest

CLI = os.environ.get("MOREAU_CLI", "moreau")
ROOT = pathlib.Path(os.environ.get("MOREAU_ROOT", pathlib.Path(__file__).resolve().parents[2]))
EXAMPLES = ROOT / "examples" / "control"


def run(*args, timeout=600):
    return subprocess.run([CLI, "control", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def test_oscillator_run_writes_summary_trajectory_and_controls(tmp_path):
    out = tmp_path / "osc"
    r = run(EXAMPLES / "oscillator_1d.toml", "--set", "discretization.steps=500", "--out", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    for key in ("ok", "value", "newton_iterations", "residual_norm", "total_seconds",
                "steps"):
        assert key in summary
    assert summary["ok"] is True
    assert summary["steps"] == 500
    assert summary["residual_norm"] < 1e-10
    assert summary["value"] > 0
    assert summary["settings"]["oscillator"]["mass"] == 100.0
    rows = read_csv(out / "trajectory.csv")
    assert rows[0][:3] == ["t", "node0_x0", "node1_x0"]
    assert len(rows) == 1 + 501
    assert float(rows[-1][0]) == pytest.approx(2.0)
    assert float(rows[-1][2]) == pytest.approx(1.01, abs=2e-4)  # the mass reached the target
    controls = read_csv(out / "controls.csv")
    assert controls[0] == ["t", "spring0_0_1"]
    assert len(controls) == 1 + 500
    lengths = [float(c[1]) for c in controls[1:]]
    assert 0.5 <= min(lengths) and max(lengths) <= 1.515
    # Progress never goes to stdout/stderr when they are not terminals.
    assert "\r" not in r.stderr


def test_network_scenario_with_gaps_runs(tmp_path):
    out = tmp_path / "net"
    r = run(EXAMPLES / "network_2d.toml", "--out", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["ok"] is True
    header = read_csv(out / "trajectory.csv")[0]
    assert header[:7] == ["t", "node0_x0", "node0_x1", "node1_x0", "node1_x1", "node2_x0",
                          "node2_x1"]
    assert "ref1_w" in header


def test_study_writes_table_and_figures(tmp_path):
    out = tmp_path / "study"
    r = run(EXAMPLES / "oscillator_1d.toml", "--study-steps", "250,500,1000", "--out", out)
    assert r.returncode == 0, r.stderr
    rows = read_csv(out / "convergence.csv")
    header, body = rows[0], rows[1:]
    assert [int(b[0]) for b in body] == [250, 500, 1000]
    col = {name: i for i, name in enumerate(header)}
    for b in body:
        assert b[col["ok"]] == "1"
        assert float(b[col["residual_norm"]]) < 1e-10
        lower, upper = float(b[col["bound_lower"]]), float(b[col["bound_upper"]])
        assert lower <= float(b[col["value_minus_finest"]]) <= upper
    assert float(body[2][col["diff_previous"]]) < float(body[1][col["diff_previous"]])
    summary = json.loads((out / "summary.json").read_text())
    assert summary["steps"] == [250, 500, 1000]
    assert summary["ok"] is True
    for fig in ("value_vs_steps.png", "difference_vs_steps.png"):
        assert (out / fig).stat().st_size > 1000


def test_newton_failure_is_reported_not_crashed(tmp_path):
    out = tmp_path / "fail"
    r = run(EXAMPLES / "oscillator_1d.toml", "--set", "newton.max_iterations=1", "--set",
            "discretization.steps=200", "--out", out)
    assert r.returncode == 3
    summary = json.loads((out / "summary.json").read_text())
    assert summary["ok"] is False
    assert summary["termination"] == "max_iterations"
    assert "did not converge" in summary["message"]
    assert (out / "trajectory.csv").exists()  # the best iterate is kept


BASE = (EXAMPLES / "network_2d.toml").read_text()


def bad_case(name):
    """(scenario text, expected key, expected reason fragment) for each bad input of the model."""
    if name == "disconnected":
        text = BASE.replace("  { mass = 1.0, position = [0.5, -0.8] },",
                            "  { mass = 1.0, position = [0.5, -0.8] },\n"
                            "  { mass = 1.0, position = [5.0, 5.0] },")
        return text, "network.springs", "disconnected"
    if name == "fixed_pair":
        text = BASE.replace("  { mass = 1.0, position = [0.5, -0.8] },",
                            "  { mass = 1.0, position = [0.5, -0.8] },\n"
                            "  { fixed = true, position = [0.0, 1.0] },")
        text = text.replace("rest_min = 0.65, rest_max = 1.25 },\n]",
                            "rest_min = 0.65, rest_max = 1.25 },\n"
                            "  { nodes = [0, 3], stiffness = 1.0, damping = 1.0, rest_min = 0.5,"
                            " rest_max = 1.5 },\n]")
        return text, "network.springs[3].nodes", "two fixed nodes"
    if name == "bounds":
        text = BASE.replace("rest_min = 0.7, rest_max = 1.3", "rest_min = 1.3, rest_max = 0.7")
        return text, "network.springs[0].rest_max", "exceeds"
    if name == "mass":
        text = BASE.replace("{ mass = 1.0, position = [1.0, 0.0] }",
                            "{ mass = -1.0, position = [1.0, 0.0] }")
        return text, "network.nodes[1].mass", "positive"
    if name == "time_step":
        return BASE.replace("steps = 200", "steps = 0"), "discretization.steps", "time step"
    if name == "horizon":
        return BASE.replace("horizon = 2.0", "horizon = -2.0"), "problem.horizon", "> 0"
    if name == "reference_length":
        text = BASE.replace("  [1.02, 0.05, 0.52, -0.78],", "  [1.02, 0.05, 0.52],")
        return text, "reference.positions[1]", "wrong length"
    if name == "reference_columns":
        text = re.sub(r"positions = \[\n(.*?)\n\]",
                      "positions = [[1.0, 0.0, 0.5], [1.0, 0.0, 0.5]]", BASE, flags=re.S)
        return text, "reference.positions", "wrong length"
    if name == "coincide":
        text = BASE.replace("{ mass = 1.0, position = [0.5, -0.8] }",
                            "{ mass = 1.0, position = [1.0, 0.0] }")
        return text, "network.springs[2].nodes", "coincide"
    if name == "unknown_key":
        return BASE + "\n[newton]\nresidual_tolerence = 1e-9\n", "newton.residual_tolerence", \
            "unknown key"
    if name == "coarse_steps":
        return BASE + "\n[continuation]\ncoarse_steps = -1\n", "continuation.coarse_steps", "-1"
    if name == "refine_factor":
        return BASE + "\n[continuation]\nrefine_factor = 1\n", "continuation.refine_factor", "≥ 2 (got 1)"
    if name == "start_steps":
        return BASE + "\n[continuation]\nstart_steps = -3\n", "continuation.start_steps", "-3"
    if name == "newton_threads":
        return BASE + "\n[newton]\nthreads = -2\n", "newton.threads", "-2"
    raise ValueError(name)


@pytest.mark.parametrize("name", ["disconnected", "fixed_pair", "bounds", "mass", "time_step",
                                  "horizon", "reference_length", "reference_columns", "coincide",
                                  "unknown_key", "coarse_steps", "refine_factor",
                                  "start_steps", "newton_threads"])
def test_bad_input_one_line_exit_2_nothing_written(tmp_path, name):
    text, key, reason = bad_case(name)
    scenario = tmp_path / f"bad_{name}.toml"
    scenario.write_text(text)
    out = tmp_path / "out"
    r = run(scenario, "--out", out)
    assert r.returncode == 2, (r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    line = lines[0]
    assert str(scenario) in line
    assert key in line, line
    assert reason in line, line
    assert r.stdout == ""
    assert not out.exists() or not any(out.iterdir())


def test_bad_set_override_and_study_steps(tmp_path):
    out = tmp_path / "out"
    r = run(EXAMPLES / "oscillator_1d.toml", "--set", "oscillator.mass=0", "--out", out)
    assert r.returncode == 2
    assert "oscillator_1d.toml" in r.stderr and "mass" in r.stderr
    r = run(EXAMPLES / "oscillator_1d.toml", "--study-steps", "400,200", "--out", out)
    assert r.returncode == 2
    assert "--study-steps" in r.stderr and "increase" in r.stderr
    assert not out.exists() or not any(out.iterdir())
