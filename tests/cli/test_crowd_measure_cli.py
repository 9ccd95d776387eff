"""Crowd measurements through the tool: `moreau run` writes trajectory.txt (PedPy's text format)
holding the positions of trajectory.h5, and `moreau measure` gets exact densities, speeds and
crossing times on a walking lattice. With MOREAU_CROWDS_VENV (a venv with
tests/crowds/requirements.txt) PedPy reads the file and its densities agree with ours."""
import csv
import json
import os
import pathlib
import subprocess

import h5py
import numpy as np
import pytest

from conftest import CROWD, ROOT, run_cli, rejected

SHORT_CROWD = ["--set", "problem.T=2", "--set", "problem.count=60", "--set", "output.stride=100",
               "--set", "output.vtu=false", "--set", "output.snapshots=false",
               "--set", "output.snapshot_times=[]",
               "--set", "output.trajectory_txt=true"]


def read_txt(path):
    """(header lines, rows id frame x y z as a float array)."""
    lines = path.read_text().splitlines()
    header = [line for line in lines if line.startswith("#")]
    rows = np.array([[float(w) for w in line.split()] for line in lines
                     if line and not line.startswith("#")])
    return header, rows


def test_trajectory_txt_holds_the_hdf5_positions(tmp_path):
    out = tmp_path / "crowd"
    r = run_cli("run", CROWD, "--out", out, *SHORT_CROWD)
    assert r.returncode == 0, r.stderr
    assert "trajectory.txt" in r.stdout
    header, rows = read_txt(out / "trajectory.txt")
    assert "# framerate: 5 fps" in header  # 1 / (h · stride) = 1 / (0.002 s · 100)
    assert "# id frame x/m y/m z/m" in header
    with h5py.File(out / "trajectory.h5", "r") as f:
        steps = f["step"][()]
        x = f["positions"][()]
        ids = f["ids"][()]
    on_stride = np.flatnonzero(steps % 100 == 0)
    assert len(on_stride) == 11 and rows.shape == (11 * 60, 5)
    for k, frame in enumerate(on_stride):
        block = rows[60 * k:60 * (k + 1)]
        assert np.all(block[:, 1] == steps[frame] // 100)
        assert np.array_equal(block[:, 0], ids[frame])
        assert np.max(np.abs(block[:, 2:4] - x[frame])) <= 5e-7 + 1e-12  # six decimals
        assert np.all(block[:, 4] == 0.0)


def lattice_trajectory(path, a=0.8, v=0.5, fps=4.0, frames=21):
    """A 12 × 8 square lattice of spacing a walking at v along +x, written with 6 decimals."""
    lines = [f"# framerate: {fps:g} fps", "# x, y, z in m", "# id frame x/m y/m z/m"]
    for f in range(frames):
        for j in range(8):
            for i in range(12):
                lines.append(f"{12 * j + i} {f} {i * a + v * f / fps:.6f} {j * a:.6f} 0.000000")
    path.write_text("\n".join(lines) + "\n")


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_measure_is_exact_on_a_walking_lattice(tmp_path):
    a, v, fps = 0.8, 0.5, 4.0
    traj = tmp_path / "lattice" / "trajectory.txt"
    traj.parent.mkdir()
    lattice_trajectory(traj, a, v, fps)
    # Interior area: rows 2 … 5 of the lattice cover it for every frame; a line at x = 6.1.
    r = run_cli("measure", traj, "--area", "mid=3.0,1.3,5.5,4.1", "--line", "exit=6.1,-1,6.1,7",
                "--bound", "-1,-1,16,7")
    assert r.returncode == 0, r.stderr
    out = tmp_path / "lattice_measure"
    rows = read_csv(out / "measurements.csv")
    mid = [row for row in rows if row["name"] == "mid"]
    assert len(mid) == 21
    for row in mid:
        t = float(row["t"])
        assert abs(float(row["density_voronoi"]) - 1 / a**2) < 1e-6, row
        assert abs(float(row["speed_voronoi"]) - v) < 1e-6, row
        inside = sum(3.0 < i * a + v * t < 5.5 for i in range(12)) * sum(
            1.3 < j * a < 4.1 for j in range(8))
        assert int(row["count"]) == inside
        assert abs(float(row["density_classic"]) - inside / (2.5 * 2.8)) < 1e-9
    # Column i crosses x = 6.1 at t = (6.1 − i a) / v, eight people at a time.
    expected = sorted((6.1 - i * a) / v for i in range(12) if 0 < (6.1 - i * a) / v <= 5.0)
    crossings = read_csv(out / "crossings.csv")
    times = sorted({round(float(c["t"]), 9) for c in crossings})
    assert np.allclose(times, expected, atol=1e-6)
    assert len(crossings) == 8 * len(expected)
    line = json.loads((out / "summary.json").read_text())["lines"][0]
    assert line["crossings"] == 8 * len(expected) and line["length"] == 8.0
    n = line["crossings"]
    assert abs(line["flow"] - (n - 1) / (expected[-1] - expected[0])) < 1e-6
    assert abs(line["specific_flow"] - line["flow"] / 8.0) < 1e-12
    for row in rows:
        if row["name"] == "exit":
            t = float(row["t"])
            assert int(row["crossings"]) == 8 * sum(c <= t + 1e-9 for c in expected)


def test_measure_rejects_bad_input_in_one_line(tmp_path):
    traj = tmp_path / "l" / "trajectory.txt"
    traj.parent.mkdir()
    lattice_trajectory(traj, frames=3)
    rejected(run_cli("measure", traj, "--area", "a=1,2,3"), "--area", "rectangle")
    rejected(run_cli("measure", traj, "--line", "l=1,1,1,1"), "--line", "a and b must differ")
    rejected(run_cli("measure", traj, "--area", "a=0,0,1,1", "--bound", "0,0,2,0,1,0.1,2,2,0,2"),
             "--bound", "convex")
    rejected(run_cli("measure", traj, "--area", "a=0,0,1,1", "--cutoff", "0"),
             "--cutoff: must be > 0")
    rejected(run_cli("measure", traj), "at least one --area or --line")
    rejected(run_cli("measure", tmp_path / "none.txt", "--line", "l=0,0,0,1"), "does not exist")
    assert not (tmp_path / "l_measure").exists()
    # Agent-based runs do not write it (yet): one line, not a silently missing file.
    r = run_cli("run", ROOT / "examples/abm/crowd_exit.toml", "--out", tmp_path / "abm",
                "--set", "output.trajectory_txt=true")
    rejected(r, "output.trajectory_txt", "not written for agent-based runs")


PEDPY_CHECK = r"""
import json, sys, pathlib
import numpy as np, pandas as pd
from pedpy import (load_trajectory, WalkableArea, MeasurementArea, TrajectoryUnit,
                   compute_individual_voronoi_polygons, compute_intersecting_polygons,
                   compute_voronoi_density, compute_classic_density, Cutoff)
traj_file, ours, cutoff = pathlib.Path(sys.argv[1]), sys.argv[2], float(sys.argv[3])
traj = load_trajectory(trajectory_file=traj_file)
walkable = WalkableArea([(0, 0), (15, 0), (15, 15), (0, 15)])
area = MeasurementArea([(9, 4), (14, 4), (14, 11), (9, 11)])
polys = compute_individual_voronoi_polygons(
    traj_data=traj, walkable_area=walkable,
    cut_off=Cutoff(radius=cutoff, quad_segments=3) if cutoff > 0 else None)
density, _ = compute_voronoi_density(individual_voronoi_data=polys, measurement_area=area)
classic = compute_classic_density(traj_data=traj, measurement_area=area)
density = density.set_index("frame") if "frame" in density.columns else density
classic = classic.set_index("frame") if "frame" in classic.columns else classic
ref = pd.read_csv(ours)
ref = ref[ref.name == "a"].set_index("frame")
print(json.dumps({"frame_rate": traj.frame_rate, "rows": len(traj.data),
                  "voronoi": float(np.max(np.abs(density.density - ref.density_voronoi))),
                  "classic": float(np.max(np.abs(classic.density - ref.density_classic))),
                  "frames": len(density), "mean": float(density.density.mean())}))
"""


@pytest.mark.skipif(not os.environ.get("MOREAU_CROWDS_VENV"),
                    reason="MOREAU_CROWDS_VENV (a venv with tests/crowds/requirements.txt) not set")
def test_pedpy_reads_the_trajectory_and_agrees_on_densities(tmp_path):
    python = pathlib.Path(os.environ["MOREAU_CROWDS_VENV"]) / "bin" / "python"
    out = tmp_path / "crowd"
    r = run_cli("run", CROWD, "--out", out, *SHORT_CROWD, "--set", "problem.count=150")
    assert r.returncode == 0, r.stderr
    script = tmp_path / "pedpy_check.py"
    script.write_text(PEDPY_CHECK)
    for cutoff in (0.0, 0.8):
        flags = ["--cutoff", str(cutoff)] if cutoff > 0 else []
        m = tmp_path / f"measure_{cutoff}"
        r = run_cli("measure", out / "trajectory.txt", "--area", "a=9,4,14,11",
                    "--bound", "0,0,15,15", "--out", m, *flags)
        assert r.returncode == 0, r.stderr
        p = subprocess.run([python, script, out / "trajectory.txt", m / "measurements.csv",
                            str(cutoff)], capture_output=True, text=True, timeout=300)
        assert p.returncode == 0, p.stderr
        got = json.loads(p.stdout.strip().splitlines()[-1])
        assert got["frame_rate"] == 5.0 and got["rows"] == 11 * 150 and got["frames"] == 11
        assert got["mean"] > 0.3, got  # people are in the area
        # Same cells from the same six-decimal positions: rounding apart (and measurements.csv's
        # twelve digits), the same numbers.
        assert got["voronoi"] < 1e-9, got
        assert got["classic"] < 1e-10, got
        print(cutoff, got)


def test_door_line_counts_what_the_evacuation_count_counts(tmp_path):
    """A line across the door, measured on trajectory.txt, gives at every frame the count of
    people out that the run itself keeps per step (evacuation.csv: centres past x = 15)."""
    out = tmp_path / "room"
    r = run_cli("run", CROWD, "--out", out, *SHORT_CROWD, "--set", "problem.T=12",
                "--set", "output.stride=50")
    assert r.returncode == 0, r.stderr
    r = run_cli("measure", out / "trajectory.txt", "--line", "door=15,5,15,10", "--out",
                tmp_path / "m")
    assert r.returncode == 0, r.stderr
    evacuation = {round(float(row["t"]), 6): int(row["out"])
                  for row in read_csv(out / "evacuation.csv")}
    door = [row for row in read_csv(tmp_path / "m" / "measurements.csv") if row["name"] == "door"]
    assert len(door) == 121
    for row in door:
        assert int(row["crossings"]) == evacuation[round(float(row["t"]), 6)], row
    assert int(door[-1]["crossings"]) > 20  # people did leave
