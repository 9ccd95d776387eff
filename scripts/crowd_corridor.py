#!/usr/bin/python3
"""Two-dimensional fundamental diagram of the collision-free speed model (docs/crowds.md).

For each global density rho (persons per square metre) N = rho L W people walk along a corridor of
length L = 20 m (periodic) and width W = 3 m between two walls (`domain.box_walls`, the
half-spaces y >= 0 and y <= W), desired direction +x, desired speed v0 = 1.34 m/s, the model's
default parameters (T = 1 s, l = 0.3 m, a = 5, D = 0.1 m; walls a_w = 5, D_w = 0.02 m). They
start at random (the engine's random sequential addition, centres at least 0.2 m from the walls,
seeded); the mean speed along the corridor over the second half of a 60 s run is the stationary
speed, three seeds per density (the CSV also records how often the engine's non-overlap
projection acted, summary.json `projections`). It is compared with Weidmann's (1993)
speed-density relation (Kladek's formula) and with the unidirectional corridor experiments of
Zhang et al. (2011), docs/results/crowds/corridor_experiments.csv.

usage: scripts/crowd_corridor.py MOREAU OUT_DIR [--figure PNG] [--csv CSV] [--densities RHO ...]
                                 [--seeds N] [--step H]
"""
import csv
import json
import math
import pathlib
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import crowd_single_file  # noqa: E402

DENSITIES = [0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0]
LENGTH, WIDTH = 20.0, 3.0
V0 = 1.34
WEIDMANN = (1.34, 1.913, 5.4)  # free speed (m/s), gamma (1/m^2) and rho_max (1/m^2)
DURATION, STEP = 60.0, 0.01
ROOT = pathlib.Path(__file__).resolve().parents[1]
EXPERIMENT = ROOT / "docs/results/crowds/corridor_experiments.csv"


def people(rho, length=LENGTH, width=WIDTH):
    return max(1, round(rho * length * width))


def scenario(rho, duration=DURATION, seed=1, length=LENGTH, width=WIDTH, extra=(), radius=0.15,
             step=STEP):
    """The TOML text of the corridor at global density rho (persons/m^2); extra: lines added
    to [forces], radius: the bodies' radius (l/2), step: the time step h (frames every 0.1 s)."""
    count = people(rho, length, width)
    lines = "\n".join(extra)
    return f"""[problem]
kind = "particles"
dimension = 2
count = {count}
radius = {radius!r}
T = {duration}
seed = {seed}

[domain]
lo = [0.0, 0.0]
hi = [{length!r}, {width!r}]
periodic = [true, false]
box_walls = true

[initial]
lo = [0.0, 0.2]
hi = [{length!r}, {width - 0.2!r}]

[forces]
propulsion_speed = {V0}
direction = [1.0, 0.0]
pedestrian_model = "collision_free"
{lines}

[solver]
h = {step!r}

[output]
stride = {crowd_single_file.frame_stride(step)}
vtu = false
snapshots = false
"""


def mean_speed(out, length=LENGTH):
    """The mean speed along x over the second half of the run (as on the single-file ring)."""
    return crowd_single_file.mean_speed(out, length)


def weidmann(rho):
    v0, gamma, rho_max = WEIDMANN
    return v0 * (1.0 - math.exp(-gamma * (1.0 / rho - 1.0 / rho_max))) if rho < rho_max else 0.0


def run(moreau, out, name, text):
    toml = out / f"{name}.toml"
    toml.write_text(text)
    run_dir = out / name
    shutil.rmtree(run_dir, ignore_errors=True)
    r = subprocess.run([moreau, "run", str(toml), "--out", str(run_dir)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{name}: {r.stderr.strip()}")
    return run_dir


def main():
    ap = crowd_single_file.study_parser(__doc__, "corridor_fd.png", "corridor_simulated.csv")
    ap.add_argument("--densities", type=float, nargs="+", default=DENSITIES)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--step", type=float, default=STEP, help="time step h (s)")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for rho in args.densities:
        for seed in range(1, args.seeds + 1):
            text = scenario(rho, seed=seed, step=args.step)
            out = run(args.moreau, args.out, f"corridor_{rho}_s{seed}", text)
            v = mean_speed(out)
            with open(out / "summary.json") as f:
                projections = json.load(f)["projections"]
            rows.append((rho, people(rho), seed, v, weidmann(rho), projections))
            print(f"rho = {rho:g} /m^2 (N = {people(rho)}), seed {seed}: v = {v:.3f} m/s, "
                  f"Weidmann {weidmann(rho):.3f}")
    args.csv.parent.mkdir(parents=True, exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["density_per_m2", "people", "seed", "simulated_speed_m_s",
                    "weidmann_speed_m_s", "projections"])
        for rho, count, seed, v, wd, projections in rows:
            w.writerow([rho, count, seed, f"{v:.4f}", f"{wd:.4f}", projections])
    plot(rows, args.figure)


def experiments():
    with open(EXPERIMENT) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def plot(rows, figure):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    grid = np.linspace(0.1, 5.4, 300)
    ax.plot(grid, [weidmann(r) for r in grid], "k-", lw=1,
            label="Weidmann 1993 (Kladek form: v0 1.34, γ 1.913, ρmax 5.4)")
    zhang = [r for r in experiments() if r["source"].startswith("Zhang")]
    ax.plot([float(r["density_per_m2"]) for r in zhang], [float(r["speed_m_s"]) for r in zhang],
            "s", color="C3", mfc="none", label="Zhang et al. 2011, corridor 3 m (run means)")
    ax.plot([r[0] for r in rows], [r[3] for r in rows], ".", color="C0", alpha=0.5)
    densities = sorted({r[0] for r in rows})
    means = [np.mean([r[3] for r in rows if r[0] == rho]) for rho in densities]
    ax.plot(densities, means, "o-", color="C0",
            label="collision-free model, 20 m × 3 m periodic corridor (3 seeds)")
    ax.set_xlabel("density ρ (persons/m²)")
    ax.set_ylabel("mean speed (m/s)")
    ax.set_title("Two-dimensional fundamental diagram (unidirectional)")
    ax.legend(fontsize=7)
    ax.set_xlim(0, 5.5)
    ax.set_ylim(0, 1.7)
    fig.tight_layout()
    fig.savefig(figure, dpi=120)


if __name__ == "__main__":
    main()
