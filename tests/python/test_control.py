"""moreau.control: the oscillator example solved as `moreau control` solves it (bit for bit),
networks and tracking problems from numpy, errors."""
import json

import numpy as np
import pytest

import moreau
from moreau import control
from conftest import ROOT, run_cli


@pytest.fixture(scope="module")
def oscillator_cli(tmp_path_factory):
    """summary.json of `moreau control examples/control/oscillator_1d.toml` on 200 steps."""
    out = tmp_path_factory.mktemp("oscillator")
    run_cli("control", ROOT / "examples/control/oscillator_1d.toml", "--set",
            "discretization.steps=200", "--out", out)
    return json.loads((out / "summary.json").read_text())


def test_oscillator_equals_moreau_control(oscillator_cli):
    cli = oscillator_cli
    example = control.OscillatorExample()  # the file's [oscillator] values are the defaults
    newton = control.NewtonOptions(residual_tolerance=1e-13)  # the file's [newton]
    r = control.solve(example, 200, path_start=1.0, gamma_start=0.0, newton=newton)
    assert r["summary"].ok and r["summary"].termination == "converged"
    assert r["value"] == cli["value"] and r["residual_norm"] == cli["residual_norm"]
    assert r["tracking_rms"] == cli["tracking_rms"] and r["dt"] == cli["dt"]
    assert r["states"].shape == (201, 2)


def test_tracking_problem_from_arrays():
    nodes = [control.NetworkNode(fixed=True, position=[0.0, 0.0, 0.0]),
             control.NetworkNode(mass=1.0, position=[1.0, 0.0, 0.0])]
    springs = [control.NetworkSpring(a=0, b=1, stiffness=4.0, damping=1.0, rest_min=0.5,
                                     rest_max=1.5)]
    network = control.SpringNetwork(1, nodes, springs)
    assert network.state_size == 2 and network.num_free == 1
    frames = np.linspace(0.0, 1.0, 11)
    reference = (1.0 + 0.1 * frames).reshape(-1, 1)  # F × (d M)
    problem = control.TrackingProblem(network, 1.0, reference, gamma=1e-3)
    r = control.solve(problem, 50)
    assert r["summary"].ok
    assert r["tracking_rms"] < 0.05
    assert set(r["summary"].to_dict()) >= {"termination", "ok", "message", "total_seconds",
                                           "settings"}


def test_errors_name_the_field():
    with pytest.raises(ValueError, match=r"^network.nodes\[1\].mass"):
        control.SpringNetwork(1, [control.NetworkNode(fixed=True),
                                  control.NetworkNode(mass=-1.0, position=[1.0, 0, 0])],
                              [control.NetworkSpring(a=0, b=1)])
    with pytest.raises(ValueError, match=r"^path_start"):
        control.ContinuationOptions(path_start=2.0)
    with pytest.raises(ValueError, match="linear solver|riccati|sparse_lu"):
        control.NewtonOptions(linear_solver="cholesky")



GRID_FIELDS = ("coarse_steps", "refine_factor", "start_steps")  # the coarse-to-fine grids


def test_grid_defaults_are_the_cli_defaults(oscillator_cli):
    # The oscillator file sets no grid key and no newton.threads: the CLI reports the defaults.
    cli = oscillator_cli["settings"]
    options = control.ContinuationOptions()
    bound = options.to_dict()  # the C++ struct's ToJson
    for field in GRID_FIELDS:
        assert getattr(options, field) == bound[field] == cli["continuation"][field], field
    threads = control.NewtonOptions().threads
    assert threads == bound["newton"]["threads"] == cli["newton"]["threads"]


@pytest.mark.parametrize("field, value", [("coarse_steps", -1), ("refine_factor", 1),
                                          ("start_steps", -3)])
def test_bad_grid_option_names_the_field(field, value):
    with pytest.raises(ValueError, match=rf"^{field}: .*\(got {value}\)$"):
        control.ContinuationOptions(**{field: value})
    with pytest.raises(ValueError, match=rf"^{field}: "):
        control.solve(control.OscillatorExample(), 20, **{field: value})


def test_bad_newton_threads_names_the_field():
    with pytest.raises(ValueError, match=r"^threads: .*\(got -1\)$"):
        control.NewtonOptions(threads=-1)


def test_start_steps_reaches_the_default_controls():
    # The oscillator on N = 200 with δ continuation (gamma_start > γ): the stages before γ run on
    # the largest grid of the chain 200, 100, 50 that is <= start_steps (the default: 50; here
    # also 100), the γ stages on 200. The last solve is Newton on 200 steps either way, so both
    # reach that grid's root: controls within 1e-8 (docs/control.md, the coarse-to-fine tests).
    # One thread: OpenMP teams on a loaded 2-core machine cost more than these small solves.
    example = control.OscillatorExample()
    newton = control.NewtonOptions(residual_tolerance=1e-13, threads=1)
    default = control.ContinuationOptions(gamma_start=1.0, newton=newton)
    other = control.ContinuationOptions(gamma_start=1.0, newton=newton, start_steps=100)
    a = control.solve(example, 200, default)
    b = control.solve(example, 200, other)
    grids_a = [g["steps"] for g in a["summary"].grids]
    grids_b = [g["steps"] for g in b["summary"].grids]
    assert grids_a[0] < grids_b[0] == 100 and grids_a[-1] == grids_b[-1] == 200
    assert a["summary"].reached["gamma"] == b["summary"].reached["gamma"] == example.gamma
    assert np.max(np.abs(a["controls"] - b["controls"])) < 1e-8
