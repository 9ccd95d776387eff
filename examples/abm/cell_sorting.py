#!/usr/bin/python3
"""Cell sorting by differential adhesion against equal adhesion (docs/abm.md "Cell sorting").

Runs examples/abm/cell_sorting.toml (400 cells, two types, a random 50/50 mixture) for each seed
twice: as it is (differential adhesion, dark–dark strongest) and as the control, with every pair
of types at the dark–light stiffness (equal adhesion). Each run's start (one engine step) is run
too, for the snapshots. The segregation index (population.csv's `segregation`: the mean fraction
of a cell's touching neighbours that share its type; 0.5 for a random 50/50 mixture, 1 when
sorted) is plotted against time, with snapshots of the first seed at the start and the end
coloured by type.

Usage: cell_sorting.py MOREAU OUT_DIR [--seeds N] [--plot-only]
Writes OUT_DIR/<case>_seed<s>/ (the runs), OUT_DIR/cell_sorting.csv (t and the index of every
run) and OUT_DIR/cell_sorting.png. Exits with status 2 and a one-line message on a failed run.
"""
import argparse
import csv
import pathlib
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

HERE = pathlib.Path(__file__).parent
SCENARIO = HERE / "cell_sorting.toml"
EQUAL = 1.25  # the control: every pair at the example's dark–light stiffness
CASES = {
    "sorting": [],
    "control": [f"population.adhesion.{a}={EQUAL}"
                for a in ("dark.dark", "dark.light", "light.light")],
}
LABELS = {"sorting": "differential adhesion (k_dd = 4, k_dl = 1.25, k_ll = 1)",
          "control": f"equal adhesion (every pair {EQUAL})"}
COLOURS = {"sorting": "tab:red", "control": "tab:blue"}
TYPE_COLOURS = ("#3b3b3b", "#f2c14e")  # dark, light


def fail(message):
    print(f"cell_sorting.py: {message}", file=sys.stderr)
    sys.exit(2)


def run(moreau, out, settings, start):
    command = [moreau, "run", str(SCENARIO), "--out", str(out), "--set", "output.hdf5=false",
               "--set", "output.vtu=false"]
    for s in settings + (["problem.T=0.05"] if start else []):
        command += ["--set", s]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"{' '.join(command)}: {done.stderr.strip()}")


def segregation(path):
    rows = list(csv.DictReader(open(path)))
    return [float(r["t"]) for r in rows], [float(r["segregation"]) for r in rows]


def snapshot(ax, path, title, extent):
    rows = list(csv.DictReader(open(path)))
    disks = [Circle((float(r["x"]), float(r["y"])), float(r["r"])) for r in rows]
    collection = PatchCollection(disks, facecolors=[TYPE_COLOURS[int(r["type"])] for r in rows],
                                 edgecolors="k", linewidths=0.2)
    ax.add_collection(collection)
    ax.set_xlim(-extent, extent)
    ax.set_ylim(-extent, extent)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=9)


def plot(out, seeds):
    fig = plt.figure(figsize=(12, 6))
    grid = fig.add_gridspec(2, 3, width_ratios=[1.6, 1, 1])
    curve = fig.add_subplot(grid[:, 0])
    table = {}
    for case in CASES:
        for seed in seeds:
            t, s = segregation(out / f"{case}_seed{seed}" / "population.csv")
            table[f"{case}_seed{seed}"] = s
            curve.plot(t, s, color=COLOURS[case], lw=1.5 if seed == seeds[0] else 0.7,
                       label=LABELS[case] if seed == seeds[0] else None)
    curve.axhline(0.5, color="gray", ls=":", lw=1, label="random 50/50 mixture")
    curve.set_xlabel("time")
    curve.set_ylabel("segregation index")
    curve.set_ylim(0.3, 1.0)
    curve.grid(True, alpha=0.3)
    curve.legend(loc="lower right", fontsize=8)
    curve.set_title(f"{len(seeds)} seed(s) each", fontsize=9)
    # One scale for the four snapshots: the largest |coordinate| + 1.
    agents = [pathlib.Path(f"{out / f'{c}_seed{seeds[0]}'}{end}") / "agents.csv"
              for c in CASES for end in ("_start", "")]
    extent = 1 + max(abs(float(r[a])) for p in agents for r in csv.DictReader(open(p))
                     for a in ("x", "y"))
    for row, case in enumerate(CASES):
        first = out / f"{case}_seed{seeds[0]}"
        _, s0 = segregation(pathlib.Path(f"{first}_start") / "population.csv")
        t1, s1 = segregation(first / "population.csv")
        snapshot(fig.add_subplot(grid[row, 1]), pathlib.Path(f"{first}_start") / "agents.csv",
                 f"{case}, start: index {s0[0]:.2f}", extent)
        snapshot(fig.add_subplot(grid[row, 2]), first / "agents.csv",
                 f"{case}, t = {t1[-1]:g}: index {s1[-1]:.2f}", extent)
    fig.tight_layout()
    fig.savefig(out / "cell_sorting.png", dpi=120)
    with open(out / "cell_sorting.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["t"] + list(table))
        for i, ti in enumerate(t):
            writer.writerow([ti] + [f"{table[k][i]:.6g}" for k in table])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("moreau")
    parser.add_argument("out", type=pathlib.Path)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--plot-only", action="store_true")
    args = parser.parse_args()
    seeds = list(range(1, args.seeds + 1))
    if not args.plot_only:
        for case, settings in CASES.items():
            for seed in seeds:
                name = args.out / f"{case}_seed{seed}"
                with_seed = settings + [f"problem.seed={seed}"]
                run(args.moreau, name, with_seed, start=False)
                if seed == seeds[0]:
                    run(args.moreau, pathlib.Path(f"{name}_start"), with_seed, start=True)
    plot(args.out, seeds)


if __name__ == "__main__":
    main()
