"""End-to-end tests of `moreau run` on particle scenarios (docs/particles.md): the crowd evacuation, outputs,
and every bad input: one line naming the file, the key and the reason, exit code 2, nothing
written; a non-finite force stops with exit code 3 and keeps the last good frame."""
import csv
import json

import pytest

from conftest import ROOT, assert_rejected, run_cli

SMALL = """
[problem]
kind = "particles"
dimension = 2
count = 50
radius = 0.5
T = 1.0
seed = 2

[domain]
lo = [0.0, 0.0]
hi = [20.0, 20.0]
box_walls = true

[forces]
trap_gamma = 1.0
trap_center = [10.0, 10.0]
diffusion = 0.01

[solver]
h = 0.01
"""

TWO = """
[problem]
kind = "particles"
dimension = 2
count = 2
radius = 0.5
T = 0.1
seed = 1

[domain]
lo = [0.0, 0.0]
hi = [10.0, 10.0]

[solver]
h = 0.01

[initial]
positions = [[5.0, 5.0], [5.6, 5.0]]
"""


def test_crowd_evacuates_end_to_end(tmp_path):
    out = tmp_path / "crowd"
    r = run_cli("run", ROOT / "examples" / "crowd.toml", "--out", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "evacuation.csv") as f:
        rows = list(csv.DictReader(f))
    outs = [int(row["out"]) for row in rows]
    assert outs[0] == 0
    assert all(b >= a for a, b in zip(outs, outs[1:])), "people came back in"
    assert summary["evacuated"] == outs[-1] == 200, "everybody leaves within T"
    # Hard non-overlap: the documented tolerance is 0.02 m (a tenth of the smallest radius).
    assert summary["max_overlap"] < 0.02
    for name in ("evacuation.png", "snapshots.png", "trajectory.h5", "trajectory.xdmf",
                 "vtu/frame.pvd"):
        assert (out / name).exists(), name
    assert not list(out.parent.glob(".moreau-staging.*"))  # staged beside, then renamed


def test_same_seed_same_bits(tmp_path, write_scenario):
    path = write_scenario(SMALL)
    r1 = run_cli("run", path, "--out", tmp_path / "a", "--set", "solver.threads=1")
    r2 = run_cli("run", path, "--out", tmp_path / "b", "--set", "solver.threads=2")
    assert r1.returncode == 0 and r2.returncode == 0, r1.stderr + r2.stderr
    a = (tmp_path / "a" / "trajectory.h5").read_bytes()
    b = (tmp_path / "b" / "trajectory.h5").read_bytes()
    assert a == b


def test_fix_overlaps_makes_a_feasible_start(tmp_path, write_scenario):
    path = write_scenario(TWO)
    r = run_cli("run", path, "--out", tmp_path / "bad")
    assert r.returncode == 2
    assert "overlap" in r.stderr and "--fix-overlaps" in r.stderr
    assert not (tmp_path / "bad").exists()
    r = run_cli("run", path, "--fix-overlaps", "--out", tmp_path / "fixed")
    assert r.returncode == 0, r.stderr
    summary = json.loads((tmp_path / "fixed" / "summary.json").read_text())
    assert summary["fix_overlaps_sweeps"] >= 1
    assert summary["max_overlap"] <= 1e-9


BAD = [
    ("inside wall", TWO.replace("[5.6, 5.0]", "[5.0, 0.2]").replace("[domain]", "[[walls]]\n"
     "normal = [0.0, 1.0]\noffset = 0.0\n\n[domain]"), "initial", "inside walls[0]"),
    ("inside obstacle", TWO.replace("[5.6, 5.0]", "[8.0, 8.0]").replace("[domain]",
     "[[spheres]]\ncenter = [8.0, 8.5]\nradius = 1.0\n\n[domain]"), "initial", "inside spheres[0]"),
    ("radius too large", SMALL.replace("radius = 0.5", "radius = 6.0").replace(
        "box_walls = true", "periodic = [true, true]"), "problem", "too large"),
    ("memory", SMALL.replace("count = 50", "count = 2000000000"), "problem.count", "GiB"),
    ("radius", SMALL.replace("radius = 0.5", "radius = -1.0"), "problem.radius", "must be > 0"),
    ("h", SMALL.replace("h = 0.01", "h = 0.0"), "solver.h", "must be > 0"),
    ("unknown key", SMALL + "\n[output]\nformat = 'x'\n", "output.format", "unknown key"),
    ("dimension", SMALL.replace("dimension = 2", "dimension = 4"), "problem.dimension",
     "must be 2 or 3"),
    ("diffusion", SMALL.replace("diffusion = 0.01", "diffusion = -1.0"), "forces",
     "diffusion"),
]


@pytest.mark.parametrize("name,text,key,reason", BAD, ids=[b[0] for b in BAD])
def test_bad_particle_input(tmp_path, write_scenario, name, text, key, reason):
    assert_rejected(write_scenario(text), tmp_path / "out", key, reason)


def test_non_finite_force_stops_and_keeps_the_last_good_frame(tmp_path, write_scenario):
    # An absurd trap overflows to inf within a few steps.
    path = write_scenario(SMALL.replace("trap_gamma = 1.0", "trap_gamma = 1e306").replace(
        "h = 0.01", "h = 1.0").replace("T = 1.0", "T = 10.0").replace("box_walls = true", ""))
    out = tmp_path / "out"
    r = run_cli("run", path, "--out", out, "--set", "output.stride=1")
    assert r.returncode == 3, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["termination"] == "non_finite"
    assert summary["failed_step"] >= 1 and summary["failed_particle"] >= 0
    assert "step" in summary["message"] and "particle" in summary["message"]
    assert (out / "trajectory.h5").exists()
