#!/usr/bin/python3
"""Bottleneck flow of the collision-free speed model against the door width (docs/crowds.md).

N = 150 people (radius 0.15 m = l/2) start at random (the engine's random sequential addition,
seeded) in the waiting area [0.3, 7] m x [0.3, 7.7] m of an 8 m x 8 m `[room]` and walk out through
its door, of width b in the middle of the right wall (x = 8 m): desired speed v0 = 1.34 m/s, the
model's default parameters (T = 1 s, l = 0.3 m, a = 5, D = 0.1 m; walls a_w = 5, D_w = 0.02 m), the
same for every width. evacuation.csv counts the passages (a person passes when their centre crosses
the door line). The flow is taken from the steady part, between the 10th and the (N - 10)th passage:
J = (N - 20) / (t_(N-10) - t_10), and the specific flow is J_s = J / b. A run in which N - 10 people
are not out within 300 s counts as clogged (NaN). The CSV also records how often the engine's
non-overlap projection acted (summary.json `projections`) and the largest overlap left after a step.
The experiments' specific flows are docs/results/crowds/bottleneck_experiments.csv.

usage: scripts/crowd_bottleneck.py MOREAU OUT_DIR [--widths B ...] [--seeds N] [--step H]
                                   [--figure PNG] [--csv CSV]
"""
import csv
import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import crowd_corridor  # noqa: E402
import crowd_single_file  # noqa: E402

WIDTHS = [0.8, 1.0, 1.2, 1.6, 2.0, 2.4]
PEOPLE, SKIP = 150, 10
V0 = 1.34
T_MAX, STEP = 300.0, 0.01
ROOT = pathlib.Path(__file__).resolve().parents[1]
EXPERIMENT = ROOT / "docs/results/crowds/bottleneck_experiments.csv"


def scenario(width, seed=1, people=PEOPLE, duration=T_MAX, extra=(), radius=0.15, step=STEP):
    """The TOML text of the room with a door of the given width; extra: lines added to
    [forces], radius: the bodies' radius (l/2), step: the time step h."""
    lines = "\n".join(extra)
    return f"""[problem]
kind = "particles"
dimension = 2
count = {people}
radius = {radius!r}
T = {duration}
seed = {seed}

[room]
width = 8.0
height = 8.0
door_width = {width!r}

[domain]
lo = [0.3, 0.3]
hi = [7.0, 7.7]

[forces]
propulsion_speed = {V0}
pedestrian_model = "collision_free"
{lines}

[solver]
h = {step!r}

[output]
stride = 1000
hdf5 = false
vtu = false
snapshots = false
"""


def steady_flow(evacuation_csv, people=PEOPLE, skip=SKIP):
    """J = (N - 2 skip) / (t_(N - skip) - t_skip) from the passages; NaN when fewer are out."""
    with open(evacuation_csv) as f:
        rows = [(float(r["t"]), int(r["out"])) for r in csv.DictReader(f)]

    def first(n):
        return next((t for t, out in rows if out >= n), None)
    lo, hi = first(skip), first(people - skip)
    if hi is None or lo is None:
        return float("nan")
    return (people - 2 * skip) / (hi - lo)


def run(moreau, out, name, text):
    """Runs the scenario text as OUT/name and returns its steady flow."""
    return steady_flow(crowd_corridor.run(moreau, out, name, text) / "evacuation.csv")


def experiments():
    with open(EXPERIMENT) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def main():
    ap = crowd_single_file.study_parser(__doc__, "bottleneck_flow.png",
                                        "bottleneck_simulated.csv")
    ap.add_argument("--widths", type=float, nargs="+", default=WIDTHS)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--step", type=float, default=STEP, help="time step h (s)")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for b in args.widths:
        for seed in range(1, args.seeds + 1):
            name = f"door_{b:g}_s{seed}"
            j = run(args.moreau, args.out, name, scenario(b, seed, step=args.step))
            with open(args.out / name / "summary.json") as f:
                summary = json.load(f)
            rows.append((b, seed, j, summary["projections"], summary["max_overlap"]))
            print(f"b = {b:g} m, seed {seed}: J = {j:.3f} /s, J/b = {j / b:.3f} /(m s), "
                  f"{summary['projections']} projections")
    args.csv.parent.mkdir(parents=True, exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["door_width_m", "seed", "people", "flow_per_s", "specific_flow_per_m_s",
                    "projections", "max_overlap_m"])
        for b, seed, j, projections, overlap in rows:
            w.writerow([b, seed, PEOPLE, f"{j:.4f}", f"{j / b:.4f}", projections,
                        f"{overlap:.4f}"])
    plot(rows, args.figure)


def plot(rows, figure):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    exp = experiments()
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    js = [float(r["specific_flow_per_m_s"]) for r in exp if float(r["door_width_m"]) >= 0.8]
    ax.axhspan(min(js), max(js), color="0.85", lw=0,
               label=f"experiments' range at b ≥ 0.8 m ({min(js):.2f}–{max(js):.2f})")
    for marker, study in (("s", "Seyfried"), ("D", "Kretz"), ("^", "Liddle")):
        mine = [r for r in exp if r["source"].startswith(study)]
        ax.plot([float(r["door_width_m"]) for r in mine],
                [float(r["specific_flow_per_m_s"]) for r in mine], marker, mfc="none",
                color="0.3", label=mine[0]["source"].split(";")[0])
    widths = sorted({r[0] for r in rows})
    ax.plot([r[0] for r in rows], [r[2] / r[0] for r in rows], ".", color="C0", alpha=0.6)
    means = [np.nanmean([r[2] / r[0] for r in rows if r[0] == b]) for b in widths]
    ax.plot(widths, means, "o-", color="C0",
            label=f"collision-free model, N = {PEOPLE} (seeds: dots, mean: line)")
    ax.set_xlabel("door width b (m)")
    ax.set_ylabel("specific flow J/b (persons/(m·s))")
    ax.set_title("Bottleneck flow against door width")
    ax.set_xlim(0.3, 2.7)
    ax.set_ylim(0, 3)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(figure, dpi=120)


if __name__ == "__main__":
    main()
