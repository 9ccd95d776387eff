"""moreau.control: the oscillator example solved as `moreau control` solves it (bit for bit),
networks and tracking problems from numpy, errors."""
import json

import numpy as np
import pytest

import moreau
from moreau import control
from conftest import ROOT, run_cli


def test_oscillator_equals_moreau_control(tmp_path):
    run_cli("control", ROOT / "examples/control/oscillator_1d.toml", "--set",
            "discretization.steps=200", "--out", tmp_path)
    cli = json.loads((tmp_path / "summary.json").read_text())
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
    with pytest.raises(ValueError, match=r"^continuation\.path_start"):
        control.ContinuationOptions(path_start=2.0)
    with pytest.raises(ValueError, match="linear solver|riccati|sparse_lu"):
        control.NewtonOptions(linear_solver="cholesky")
