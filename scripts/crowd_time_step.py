#!/usr/bin/python3
"""How the collision-free speed model's validations move with the time step h (docs/crowds.md).

The single-file ring of scripts/crowd_single_file.py (one run per density), the corridor of
crowd_corridor.py and the bottleneck of crowd_bottleneck.py (three seeds per density and per
width) are run with h = 0.01, 0.02, 0.05 and 0.1 s, everything else as in those scripts (frames
every 0.1 s). h = 0.01 s is the step of the committed validations. Each run's value is the
stationary speed (m/s; ring and corridor) or the specific flow J/b (1/(m s); bottleneck), and the
largest overlap left after a step (summary.json `max_overlap`). The figure overlays the four
steps on the experiments of the three validations and plots the largest overlap against h.

usage: scripts/crowd_time_step.py MOREAU OUT_DIR [--steps H ...] [--seeds N] [--figure PNG]
                                  [--csv CSV]
"""
import csv
import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import crowd_bottleneck  # noqa: E402
import crowd_corridor  # noqa: E402
import crowd_single_file  # noqa: E402

STEPS = [0.01, 0.02, 0.05, 0.1]
STUDIES = ("single_file", "corridor", "bottleneck")


def overlap(run_dir):
    with open(run_dir / "summary.json") as f:
        return float(json.load(f)["max_overlap"])


def measure(moreau, out, step, seeds):
    """Rows (study, step, x, seed, value, largest overlap) of the three validations at step h."""
    rows = []
    for rho in crowd_single_file.DENSITIES:
        name = f"ring_{rho:g}_h{step:g}"
        run = crowd_corridor.run(moreau, out, name, crowd_single_file.scenario(rho, step=step))
        v = crowd_single_file.mean_speed(run, crowd_single_file.PEOPLE / rho)
        rows.append(("single_file", step, rho, 1, v, overlap(run)))
    for rho in crowd_corridor.DENSITIES:
        for seed in range(1, seeds + 1):
            name = f"corridor_{rho:g}_s{seed}_h{step:g}"
            run = crowd_corridor.run(moreau, out, name,
                                     crowd_corridor.scenario(rho, seed=seed, step=step))
            rows.append(("corridor", step, rho, seed, crowd_corridor.mean_speed(run),
                         overlap(run)))
    for b in crowd_bottleneck.WIDTHS:
        for seed in range(1, seeds + 1):
            name = f"door_{b:g}_s{seed}_h{step:g}"
            j = crowd_bottleneck.run(moreau, out, name,
                                     crowd_bottleneck.scenario(b, seed, step=step))
            rows.append(("bottleneck", step, b, seed, j / b, overlap(out / name)))
    return rows


def main():
    ap = crowd_single_file.study_parser(__doc__, "time_step.png", "time_step.csv")
    ap.add_argument("--steps", type=float, nargs="+", default=STEPS)
    ap.add_argument("--seeds", type=int, default=3)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for step in args.steps:
        mine = measure(args.moreau, args.out, step, args.seeds)
        rows += mine
        for study in STUDIES:
            values = [r[4] for r in mine if r[0] == study]
            print(f"h = {step:g} s, {study}: value {np.nanmin(values):.3f}–"
                  f"{np.nanmax(values):.3f}, largest overlap "
                  f"{max(r[5] for r in mine if r[0] == study):.4f} m")
    args.csv.parent.mkdir(parents=True, exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["study", "step_s", "x", "seed", "value", "max_overlap_m"])
        for study, step, x, seed, value, over in rows:
            w.writerow([study, step, x, seed, f"{value:.4f}", f"{over:.4f}"])
    plot(rows, args.figure)


def means(rows, study, step):
    """(x, mean value over the seeds) of one study at one step, in x order."""
    xs = sorted({r[2] for r in rows if r[0] == study and r[1] == step})
    return xs, [float(np.nanmean([r[4] for r in rows if r[0] == study and r[1] == step and
                                  r[2] == x])) for x in xs]


def plot(rows, figure):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    steps = sorted({r[1] for r in rows})
    fig, axes = plt.subplots(1, 4, figsize=(15, 3.8))
    with open(crowd_single_file.EXPERIMENT) as f:
        ring = list(csv.DictReader(line for line in f if not line.startswith("#")))
    axes[0].plot([float(r["density_per_m"]) for r in ring], [float(r["speed_m_s"]) for r in ring],
                 "s", color="0.3", mfc="none", label="Seyfried et al. 2005")
    zhang = [r for r in crowd_corridor.experiments() if r["source"].startswith("Zhang")]
    axes[1].plot([float(r["density_per_m2"]) for r in zhang],
                 [float(r["speed_m_s"]) for r in zhang], "s", color="0.3", mfc="none",
                 label="Zhang et al. 2011")
    grid = np.linspace(0.1, 5.4, 200)
    axes[1].plot(grid, [crowd_corridor.weidmann(x) for x in grid], "k-", lw=0.8,
                 label="Weidmann 1993")
    exp = [float(r["specific_flow_per_m_s"]) for r in crowd_bottleneck.experiments()
           if float(r["door_width_m"]) >= 0.8]
    axes[2].axhspan(min(exp), max(exp), color="0.85", lw=0,
                    label=f"experiments' range ({min(exp):.2f}–{max(exp):.2f})")
    for c, step in enumerate(steps):
        for ax, study in zip(axes[:3], STUDIES):
            xs, ys = means(rows, study, step)
            ax.plot(xs, ys, "o-", ms=3, color=f"C{c}", label=f"h = {step:g} s")
    for m, study in zip("sod", STUDIES):
        worst = [max(r[5] for r in rows if r[0] == study and r[1] == step) for step in steps]
        axes[3].plot(steps, worst, m + "-", color="k", mfc="none",
                     label=study.replace("_", "-"))
    titles = ["single file: speed (m/s) against ρ (1/m)", "corridor: speed (m/s) against ρ (1/m²)",
              "bottleneck: J/b (1/(m·s)) against b (m)", "largest overlap after a step (m)"]
    for ax, title in zip(axes, titles):
        ax.set_title(title, fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    axes[2].set_ylim(1.2, 2.4)
    axes[3].set_xscale("log")
    axes[3].set_xlabel("time step h (s)")
    fig.tight_layout()
    fig.savefig(figure, dpi=110)


if __name__ == "__main__":
    main()
