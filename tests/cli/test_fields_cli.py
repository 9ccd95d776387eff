"""Agent-based runs coupled to diffusing fields (docs/fields.md "Agents and fields"): the example's
outputs, the same bits on one and two threads and after a resume, the keys' errors, and sweeps
over a substrate's keys."""
import csv
import json

import pytest

from conftest import ROOT, rejected, run_cli

EXAMPLE = ROOT / "examples/abm/oxygen_spheroid_2d.toml"
SHORT = ["--set", "problem.T=12"]


def summary(out):
    return json.loads((out / "summary.json").read_text())


def field_bytes(out):
    """Every dataset of OUT/fields.h5 as bytes, by name."""
    h5py = pytest.importorskip("h5py")
    found = {}
    with h5py.File(out / "fields.h5", "r") as f:
        f.visititems(lambda name, obj: found.__setitem__(name, obj[...].tobytes())
                     if isinstance(obj, h5py.Dataset) else None)
    return found


def test_the_example_writes_fields_on_the_trajectory_frames(tmp_path):
    h5py = pytest.importorskip("h5py")
    out = tmp_path / "run"
    r = run_cli("run", EXAMPLE, "--out", out)
    assert r.returncode == 0, r.stderr
    assert "fields.h5 + .xdmf, vti/fields.pvd" in r.stdout
    for f in ("fields.h5", "fields.xdmf", "vti/fields.pvd", "trajectory.h5"):
        assert (out / f).exists(), f
    s = summary(out)
    assert s["scenario"]["fields"]["oxygen"]["diffusion"] == 10.0
    assert s["scenario"]["fields"]["interpolation"] == "linear"
    cell = next(t for t in s["scenario"]["types"] if t["name"] == "cell")
    assert cell["oxygen"]["uptake_rate"] == 0.5  # the types' responses are echoed too
    assert cell["oxygen"]["necrotic_type"] == "necrotic"
    with h5py.File(out / "fields.h5", "r") as f, h5py.File(out / "trajectory.h5", "r") as t:
        assert sorted(f["fields"]) == ["oxygen", "signal"]
        assert f["fields/oxygen"].shape[1:] == (32, 32)
        assert list(f["step"][...]) == list(t["step"][...])  # the same frames
        oxygen = f["fields/oxygen"][...]
        assert oxygen[0].min() == 1.0 and oxygen[-1].min() < 0.5  # taken up by the colony
    # Cells past the necrosis threshold turned necrotic, none died; divisions only where fed.
    last = (out / "population.csv").read_text().splitlines()[-1].split(",")
    assert int(last[4]) > 0 and s["deaths"] == 0 and s["births"] > 100


def test_same_bits_on_one_and_two_threads(tmp_path):
    outs = []
    for threads in (1, 2):
        out = tmp_path / f"t{threads}"
        r = run_cli("run", EXAMPLE, "--out", out, *SHORT, "--set", f"solver.threads={threads}")
        assert r.returncode == 0, r.stderr
        outs.append(out)
    assert summary(outs[0])["positions_hash"] == summary(outs[1])["positions_hash"]
    assert field_bytes(outs[0]) == field_bytes(outs[1])


def test_a_resumed_run_has_the_bits_of_an_uninterrupted_one(tmp_path):
    r = run_cli("run", EXAMPLE, "--out", tmp_path / "whole", *SHORT)
    assert r.returncode == 0, r.stderr
    r = run_cli("run", EXAMPLE, "--out", tmp_path / "a", *SHORT, "--checkpoint-every", 300)
    assert r.returncode == 0, r.stderr
    checkpoint = tmp_path / "a.checkpoint"
    assert (checkpoint / "checkpoint.bin").exists()
    # The last checkpoint (step 600 of 600 is the end; the one at 300 was overwritten by 600),
    # resumed on another thread count.
    r = run_cli("run", EXAMPLE, "--out", tmp_path / "resumed", *SHORT, "--resume", checkpoint,
                "--set", "solver.threads=2")
    assert r.returncode == 0, r.stderr
    whole, resumed = summary(tmp_path / "whole"), summary(tmp_path / "resumed")
    for key in ("positions_hash", "births", "deaths", "final_count"):
        assert resumed[key] == whole[key], key
    for f in ("population.csv", "lineage.csv", "agents.csv"):
        assert (tmp_path / "resumed" / f).read_bytes() == (tmp_path / "whole" / f).read_bytes()
    assert field_bytes(tmp_path / "resumed") == field_bytes(tmp_path / "whole")


@pytest.mark.parametrize("setting, key, reason", [
    ("fields.oxygen.diffusion=-1", "fields.oxygen.diffusion", "must be > 0"),
    ("fields.spacing=3", "fields.spacing", "not a whole number of voxels"),
    ("fields.spcing=1", "fields.spcing", "unknown key"),
    ("fields.substeps=0", "fields.substeps", "must be ≥ 1"),
    ("fields.interpolation=cubic", "fields.interpolation", "must be one of voxel, linear"),
    ("types.cell.oxygen.uptake=1", "types.cell.oxygen.uptake", "unknown key"),
    ("types.cell.oxygen.uptake_rate=-1", "types.cell.oxygen.uptake_rate", "must be ≥ 0"),
    ("types.cell.sugar.uptake_rate=1", "types.cell.sugar", "unknown substrate 'sugar'"),
    ("types.cell.oxygen.necrotic_type=dead", "types.cell.oxygen.necrotic_type", "unknown type"),
    ("types.cell.signal.secretion_variable=on", "types.cell.signal.secretion_variable",
     "unknown variable 'on'"),
    ("fields.oxygen.x_min=periodic", "fields.oxygen.x_min", "cannot be periodic"),
    ("domain.periodic=[true, false]", "fields.oxygen.x_min", "must be periodic"),
])
def test_bad_keys_are_refused_before_anything_is_written(tmp_path, setting, key, reason):
    out = tmp_path / "out"
    rejected(run_cli("run", EXAMPLE, "--out", out, "--set", setting), str(EXAMPLE), key, reason)
    assert not out.exists()


def test_fields_without_types_or_substrates_are_refused(tmp_path):
    scenario = tmp_path / "s.toml"
    scenario.write_text("[problem]\nkind = \"particles\"\ndimension = 2\ncount = 2\nT = 1.0\n"
                        "radius = 0.1\n[solver]\nh = 0.01\n[fields]\nspacing = 0.5\n[fields.oxygen]\n"
                        "diffusion = 1.0\n")
    rejected(run_cli("run", scenario, "--out", tmp_path / "o"), "fields", "needs [[types]]")
    scenario.write_text(scenario.read_text().split("[fields.oxygen]")[0])
    rejected(run_cli("run", scenario, "--out", tmp_path / "o"), "fields.spacing",
             "needs a substrate")


def test_a_sweep_reaches_a_substrates_keys_and_refuses_a_bad_one(tmp_path):
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(f'command = "run"\nscenario = "{EXAMPLE}"\ncollect = ["births"]\n'
                     "[set]\nproblem.T = 8.0\nfields.oxygen.diffusion = 2.0\n"
                     "[axes]\nfields.oxygen.initial = [0.4, 1.0]\n")
    r = run_cli("sweep", sweep, "--out", tmp_path / "out")
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "out" / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [float(row["fields.oxygen.initial"]) for row in rows] == [0.4, 1.0]
    births = [int(row["births"]) for row in rows]
    assert births[0] == 0 < births[1]  # starting below the proliferation threshold: none
    sweep.write_text(sweep.read_text().replace("oxygen.diffusion", "oxygen.difusion"))
    r = run_cli("sweep", sweep, "--out", tmp_path / "bad")
    assert r.returncode == 2 and "fields.oxygen.difusion" in r.stderr, r.stderr
    assert not (tmp_path / "bad").exists()
