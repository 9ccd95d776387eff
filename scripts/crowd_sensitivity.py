#!/usr/bin/python3
"""Sensitivity of the collision-free speed model's corridor speed and bottleneck flow to its
parameters (docs/crowds.md).

Each of T (time gap), l (length), a (repulsion), D (repulsion range) and D_w (the walls'
repulsion range) is set to 0.7 and 1.3 times the default (T = 1 s, l = 0.3 m, a = 5, D = 0.1 m,
D_w = 0.02 m; the bodies' radius follows l/2), the others kept; D_w also to 0.1 m (5 times the
default: moreau's earlier default). Measured: the mean speed in the corridor of
scripts/crowd_corridor.py at 1 and 2 persons/m^2 and the specific flow through the 1.2 m door of
scripts/crowd_bottleneck.py, each the mean over three seeds.

usage: scripts/crowd_sensitivity.py MOREAU OUT_DIR [--seeds N] [--figure PNG] [--csv CSV]
"""
import csv
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import crowd_bottleneck  # noqa: E402
import crowd_corridor  # noqa: E402
import crowd_single_file  # noqa: E402

DEFAULTS = {"time_gap": 1.0, "length": 0.3, "repulsion": 5.0, "repulsion_range": 0.1,
            "wall_repulsion_range": 0.02}
SYMBOLS = {"time_gap": "T", "length": "ℓ", "repulsion": "a", "repulsion_range": "D",
           "wall_repulsion_range": "D_w"}
FACTORS = {key: [0.7, 1.3] for key in DEFAULTS}
FACTORS["wall_repulsion_range"] = [0.7, 1.3, 5.0]
DOOR_DURATION = 160.0  # s: the 140th passage is before 110 s in every variant
DENSITIES = [1.0, 2.0]
DOOR = 1.2


def measure(moreau, out, key, value, seeds):
    """Corridor speeds at DENSITIES and the specific flow at DOOR for forces.collision_free.key =
    value (None: the defaults), means over the seeds."""
    extra = [] if key is None else [f"collision_free.{key} = {value!r}"]
    radius = value / 2 if key == "length" else 0.15
    tag = "default" if key is None else f"{key}_{value:g}"
    speeds = []
    for rho in DENSITIES:
        vs = []
        for seed in range(1, seeds + 1):
            text = crowd_corridor.scenario(rho, seed=seed, extra=extra, radius=radius)
            vs.append(crowd_corridor.mean_speed(
                crowd_corridor.run(moreau, out, f"corridor_{tag}_{rho:g}_s{seed}", text)))
        speeds.append(float(np.mean(vs)))
    flows = [crowd_bottleneck.run(moreau, out, f"door_{tag}_s{seed}",
                                  crowd_bottleneck.scenario(DOOR, seed, extra=extra,
                                                            radius=radius,
                                                            duration=DOOR_DURATION)) / DOOR
             for seed in range(1, seeds + 1)]
    return speeds, float(np.nanmean(flows))


def main():
    ap = crowd_single_file.study_parser(__doc__, "sensitivity.png", "sensitivity.csv")
    ap.add_argument("--seeds", type=int, default=3)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    base = measure(args.moreau, args.out, None, None, args.seeds)
    rows.append(("default", 1.0, None, base))
    for key, default in DEFAULTS.items():
        for factor in FACTORS[key]:
            value = round(factor * default, 6)
            rows.append((key, factor, value,
                         measure(args.moreau, args.out, key, value, args.seeds)))
    with open(args.csv, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["parameter", "factor", "value", "speed_rho1_m_s", "speed_rho2_m_s",
                    "specific_flow_b1.2_per_m_s"])
        for key, factor, value, (speeds, flow) in rows:
            w.writerow([key, factor, "" if value is None else value, f"{speeds[0]:.4f}",
                        f"{speeds[1]:.4f}", f"{flow:.4f}"])
            print(f"{key:16s} ×{factor:g}: v(1) = {speeds[0]:.3f}, v(2) = {speeds[1]:.3f}, "
                  f"J/b(1.2) = {flow:.3f}")
    plot(rows, args.figure)


def plot(rows, figure):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    base = rows[0][3]
    fig, axes = plt.subplots(1, 3, figsize=(10, 3.4), sharex=True)
    titles = ["corridor speed at 1 /m² (m/s)", "corridor speed at 2 /m² (m/s)",
              "specific flow at b = 1.2 m (1/(m·s))"]
    for panel, ax in enumerate(axes):
        def pick(m):
            return m[0][panel] if panel < 2 else m[1]
        for c, key in enumerate(DEFAULTS):
            mine = sorted([(1.0, base)] + [(r[1], r[3]) for r in rows if r[0] == key])
            ax.plot([f for f, _ in mine], [pick(m) for _, m in mine], "o-", color=f"C{c}",
                    label=SYMBOLS[key])
        ax.set_title(titles[panel], fontsize=9)
        ax.set_xlabel("factor on the default")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(figure, dpi=120)


if __name__ == "__main__":
    main()
