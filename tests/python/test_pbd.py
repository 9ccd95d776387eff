"""moreau.pbd: the same numbers as `moreau study` / `moreau run` bit for bit, Python drifts,
errors and the last good state."""
import csv
import json
import signal

import numpy as np
import pytest

import moreau
from conftest import ROOT, run_cli

# examples/sliding.toml and examples/disks.toml, [solver]: the CLI's settings for these files.
SOLVER = dict(abstol=1e-12, reltol=1e-10, max_sweeps=100000, penalty=1000.0)
SLIDING = moreau.pbd.SlidingCase(dimension=3, C=10.0, alpha=0.19634954084936207, T=4.0)


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_sliding_study_equals_moreau_study(tmp_path):
    h = [0.1, 0.05, 0.025, 0.0125]
    methods = ["pbd", "pngs", "penalty:100"]
    run_cli("study", ROOT / "examples/sliding.toml", "--methods", ",".join(methods),
            "--h", ",".join(map(repr, h)), "--out", tmp_path)
    cli = read_rows(tmp_path / "study.csv")
    py = moreau.pbd.study(SLIDING, methods, hs=h, **SOLVER)
    assert len(cli) == len(py["h"]) == len(methods) * len(h)
    for i, row in enumerate(cli):
        assert row["method"] == py["method"][i]
        assert float(row["h"]) == py["h"][i]
        assert float(row["error"]) == py["error"][i]  # %.17g round-trips: bit for bit
        assert int(row["constraint_evaluations"]) == py["constraint_evaluations"][i]
    assert set(py["termination"]) == {"completed"}


def disks_run(observer=None):
    case = moreau.pbd.DisksCase(count=40, radius=0.1, gamma=1.0, T=1.0, seed=1)
    return moreau.pbd.simulate(case.make_drift(), case.make_constraints(), case.initial_state(),
                               case.T, observer=observer, h=0.001, **SOLVER)


def test_disks_run_equals_moreau_run(tmp_path):
    run_cli("run", ROOT / "examples/disks.toml", "--out", tmp_path)
    rows = read_rows(tmp_path / "trajectory.csv")
    cli = np.array([[float(r["t"]), float(r["x"]), float(r["y"])] for r in rows])
    frames = []
    x, summary = disks_run(lambda k, t, xk: frames.append((t, xk.copy())))
    assert len(frames) == 1001 and len(rows) == 1001 * 40  # stride 1: every step
    py = np.array([[t, *xk[2 * i:2 * i + 2]] for t, xk in frames for i in range(40)])
    assert np.array_equal(cli, py)
    assert np.array_equal(x, frames[-1][1])
    cli_summary = json.loads((tmp_path / "summary.json").read_text())
    for key in ("constraint_evaluations", "sweeps", "steps", "max_violation", "final_time"):
        assert cli_summary[key] == summary.to_dict()[key] == getattr(summary, key)


def test_python_drift_gives_the_same_bits_as_the_cpp_drift():
    x0 = SLIDING.initial_state()
    x_cpp, s_cpp = moreau.pbd.simulate(SLIDING.make_drift(), SLIDING.make_constraints(), x0, 4.0,
                                       h=0.01)
    f = np.array([0.0, -1.0, 0.0])
    x_py, s_py = moreau.pbd.simulate(lambda x: f, SLIDING.make_constraints(), x0, 4.0, h=0.01)
    assert np.array_equal(x_cpp, x_py)
    assert s_cpp.constraint_evaluations == s_py.constraint_evaluations


def test_user_sets_in_python():
    ball = moreau.pbd.BallInterior([0.0, 0.0], 1.0)
    y, moved = ball.project(np.array([3.0, 4.0]))
    assert moved and np.allclose(y, [0.6, 0.8])
    disk = moreau.pbd.FunctionSet(2, lambda x: 1.0 - x @ x, lambda x: -2.0 * x)
    sets = moreau.pbd.ConstraintSetList(2, [disk, moreau.pbd.HalfSpace([0.0, 1.0], 0.0)])
    x, s = moreau.pbd.simulate(moreau.pbd.ConstantDrift([0.0, -1.0]), sets, [0.5, 0.5], 1.0,
                               h=0.01)
    assert s.ok and s.termination == "completed" and abs(x[1]) < 1e-12


def test_options_errors_carry_the_cpp_messages():
    with pytest.raises(ValueError, match=r"^h: must be > 0 \(got 0\)$"):
        moreau.pbd.StepperOptions(h=0.0)
    with pytest.raises(ValueError, match=r'^method: must be one of pbd, pngs, pgs, penalty \(got "foo"\)$'):
        moreau.pbd.StepperOptions(method="foo")
    with pytest.raises(ValueError, match=r"^StepperOptions: unknown option 'hh'$"):
        moreau.pbd.StepperOptions(hh=1.0)
    with pytest.raises(ValueError, match="whole number"):
        moreau.pbd.simulate(SLIDING.make_drift(), SLIDING.make_constraints(),
                            SLIDING.initial_state(), 4.0, h=0.3)
    with pytest.raises(ValueError, match="alpha"):
        moreau.pbd.SlidingCase(alpha=-1.0)
    with pytest.raises(ValueError, match="^h: expected a number, got a string$"):
        moreau.pbd.StepperOptions(h="small")


def test_numerical_failure_keeps_the_last_good_state():
    def drift(x):  # non-finite once the point has fallen below x_1 = 0.5
        return np.array([0.0, -1.0]) if x[1] > 0.5 else np.full(2, np.nan)

    floor = moreau.pbd.ConstraintSetList(2, [moreau.pbd.HalfSpace([0.0, 1.0], -10.0)])
    with pytest.raises(moreau.NumericalError) as info:
        moreau.pbd.simulate(drift, floor, [0.0, 1.0], 2.0, h=0.01)
    e = info.value
    assert e.summary.termination == "non_finite" and not e.summary.ok
    assert np.all(np.isfinite(e.state)) and e.state[1] <= 0.5
    assert str(e) == e.summary.message and e.summary.failed_step == 51


def test_exceptions_of_python_callbacks_propagate():
    with pytest.raises(ZeroDivisionError):
        moreau.pbd.simulate(lambda x: 1 / 0, SLIDING.make_constraints(), SLIDING.initial_state(),
                            4.0, h=0.01)


def test_ctrl_c_raises_keyboard_interrupt_between_steps():
    seen = []

    def observer(k, t, x):
        seen.append(k)
        if k == 10:
            signal.raise_signal(signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        moreau.pbd.simulate(SLIDING.make_drift(), SLIDING.make_constraints(),
                            SLIDING.initial_state(), 4.0, observer=observer, h=0.001)
    assert seen[-1] == 10  # stopped before the next observer call


def test_study_columns_and_observed_order():
    cols = moreau.pbd.study(SLIDING, ["pbd"], [0.05, 0.1, 0.025], **SOLVER)
    assert list(cols["h"]) == [0.1, 0.05, 0.025]  # sorted as `moreau study` sorts them
    assert cols["method"] == ["pbd"] * 3 and set(cols["termination"]) == {"completed"}
    order = moreau.pbd.observed_order(list(cols["h"]), list(cols["error"]))
    slope = np.polyfit(np.log(cols["h"]), np.log(cols["error"]), 1)[0]  # least squares
    assert order == pytest.approx(slope, rel=1e-12)
