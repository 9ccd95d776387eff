#!/usr/bin/python3
"""Single-file fundamental diagram of the collision-free speed model (docs/crowds.md).

For each density rho (persons per metre) N people walk in single file around a ring (an axis of
length N / rho, periodic), starting from an equal spacing moved by a seeded random shift of up to
a tenth of it; the mean speed over the second half of the run is the stationary speed. It is
compared with the model's exact stationary speed V(1/rho) = min(v0, max(0, (1/rho - l) / T)) and
with the experiment of Seyfried et al. (2005), docs/results/crowds/seyfried2005_single_file.csv.

usage: scripts/crowd_single_file.py MOREAU OUT_DIR [--figure PNG] [--csv CSV] [--step H]
"""
import argparse
import csv
import pathlib
import random
import shutil
import subprocess
import sys

import h5py
import numpy as np

DENSITIES = [0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.25, 2.5, 2.75, 3.0]
PEOPLE = 20
V0, LENGTH, TIME_GAP = 1.34, 0.3, 1.0
STEP = 0.01
ROOT = pathlib.Path(__file__).resolve().parents[1]
EXPERIMENT = ROOT / "docs/results/crowds/seyfried2005_single_file.csv"


def study_parser(doc, figure, table):
    """The crowd studies' command line: MOREAU, OUT, and --figure and --csv defaulting to these
    names in docs/results/crowds; the description is the first line of doc."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("moreau")
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--figure", type=pathlib.Path, default=ROOT / "docs/results/crowds" / figure)
    ap.add_argument("--csv", type=pathlib.Path, default=ROOT / "docs/results/crowds" / table)
    return ap


def frame_stride(step):
    """The output stride that writes a frame every 0.1 s (at least one a step)."""
    return max(1, round(0.1 / step))


def scenario(rho, people=PEOPLE, duration=40.0, seed=1, jitter=0.1, step=STEP):
    """The TOML text of the ring at density rho with time step h = step."""
    ring = people / rho
    spacing = ring / people
    rng = random.Random(seed)
    xs = [(i + 0.5) * spacing + jitter * spacing * (rng.random() - 0.5) for i in range(people)]
    positions = ", ".join(f"[{x!r}, 0.5]" for x in xs)
    return f"""[problem]
kind = "particles"
dimension = 2
count = {people}
radius = 0.15
T = {duration}
seed = {seed}

[domain]
lo = [0.0, 0.0]
hi = [{ring!r}, 1.0]
periodic = [true, false]

[initial]
positions = [{positions}]

[forces]
propulsion_speed = {V0}
direction = [1.0, 0.0]
pedestrian_model = "collision_free"
collision_free.time_gap = {TIME_GAP}
collision_free.length = {LENGTH}

[solver]
h = {step!r}

[output]
stride = {frame_stride(step)}
vtu = false
snapshots = false
"""


def mean_speed(out, ring):
    """The mean speed over the second half of the run from trajectory.h5 (minimum image)."""
    with h5py.File(out / "trajectory.h5", "r") as f:
        x = f["positions"][()][..., 0]
        t = f["time"][()]
    half = len(t) // 2
    dx = np.diff(x[half:], axis=0)
    dx -= ring * np.round(dx / ring)
    return float(dx.sum(axis=0).mean() / (t[-1] - t[half]))


def theory(rho):
    return min(V0, max(0.0, (1.0 / rho - LENGTH) / TIME_GAP))


def main():
    ap = study_parser(__doc__, "single_file_fd.png", "single_file_simulated.csv")
    ap.add_argument("--step", type=float, default=STEP, help="time step h (s)")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for rho in DENSITIES:
        toml = args.out / f"ring_{rho}.toml"
        toml.write_text(scenario(rho, step=args.step))
        run = args.out / f"ring_{rho}"
        shutil.rmtree(run, ignore_errors=True)
        r = subprocess.run([args.moreau, "run", str(toml), "--out", str(run)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"ring at density {rho}: {r.stderr.strip()}")
        rows.append((rho, mean_speed(run, PEOPLE / rho), theory(rho)))
    args.csv.parent.mkdir(parents=True, exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["density_per_m", "simulated_speed_m_s", "model_exact_speed_m_s"])
        for rho, v, exact in rows:
            w.writerow([rho, f"{v:.6f}", f"{exact:.6f}"])
    plot(rows, args.figure)


def plot(rows, figure):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with open(EXPERIMENT) as f:
        exp = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
    fig, ax = plt.subplots(figsize=(6, 4))
    grid = np.linspace(0.2, 3.1, 300)
    ax.plot(grid, [theory(r) for r in grid], "k-", lw=1,
            label=f"model, exact: min(v0, (1/ρ − {LENGTH})/{TIME_GAP})")
    ax.plot([r[0] for r in rows], [r[1] for r in rows], "o", color="C0",
            label="collision-free model, simulated ring")
    ax.plot([float(r["density_per_m"]) for r in exp], [float(r["speed_m_s"]) for r in exp], "s",
            color="C3", mfc="none", label="Seyfried et al. 2005 (fit d = 0.36 m + 1.06 s · v)")
    ax.set_xlabel("density ρ (persons/m)")
    ax.set_ylabel("mean speed (m/s)")
    ax.set_title("Single-file fundamental diagram")
    ax.legend(fontsize=8)
    ax.set_ylim(0, 1.5)
    fig.tight_layout()
    fig.savefig(figure, dpi=120)


if __name__ == "__main__":
    main()
