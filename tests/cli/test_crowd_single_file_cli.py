"""The collision-free speed model through `moreau run`: the single-file ring of
examples/crowd_single_file.toml reaches the model's exact stationary speed V(1/ρ), and bad keys
get one line and exit 2."""
import sys

import h5py
import numpy as np

from conftest import ROOT, run_cli, rejected

sys.path.insert(0, str(ROOT / "scripts"))
import crowd_single_file  # noqa: E402


def test_ring_walks_at_the_exact_stationary_speed(tmp_path):
    for rho in (0.5, 1.0, 2.5):
        toml = tmp_path / f"ring_{rho}.toml"
        toml.write_text(crowd_single_file.scenario(rho, duration=20.0))
        out = tmp_path / f"ring_{rho}"
        r = run_cli("run", toml, "--out", out)
        assert r.returncode == 0, r.stderr
        v = crowd_single_file.mean_speed(out, crowd_single_file.PEOPLE / rho)
        assert abs(v - crowd_single_file.theory(rho)) < 1e-9, (rho, v)
        with h5py.File(out / "trajectory.h5", "r") as f:
            y = f["positions"][()][..., 1]
        assert np.all(y == 0.5)  # single file: nobody leaves the line


def test_example_is_bit_identical_on_one_and_two_threads(tmp_path):
    example = ROOT / "examples/crowd_single_file.toml"
    outs = []
    for threads in (1, 2):
        out = tmp_path / f"t{threads}"
        r = run_cli("run", example, "--out", out, "--set", f"solver.threads={threads}",
                    "--set", "problem.T=5")
        assert r.returncode == 0, r.stderr
        with h5py.File(out / "trajectory.h5", "r") as f:
            outs.append(f["positions"][()])
    assert np.array_equal(outs[0], outs[1])


def test_bad_keys_are_one_line(tmp_path):
    example = ROOT / "examples/crowd_single_file.toml"
    r = run_cli("run", example, "--out", tmp_path / "a", "--set",
                "forces.collision_free.time_gap=0")
    rejected(r, "forces.collision_free.time_gap", "must be > 0")
    r = run_cli("run", example, "--out", tmp_path / "b", "--set", 'forces.pedestrian_model="x"')
    rejected(r, "forces.pedestrian_model", "unknown pedestrian model")
    r = run_cli("run", example, "--out", tmp_path / "c", "--set", "forces.density_radius=1")
    rejected(r, "forces.pedestrian_model", "does not go with forces.density_radius")
