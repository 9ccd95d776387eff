#!/usr/bin/python3
"""Flow through the door against its width (docs/abm.md "Crowds against experiments").

Runs examples/abm/crowd_exit.toml (200 pedestrians, radius 0.25 m) for every door width and seed
in three crowd models, the same rule for every width:
  constant      the example as it is: everybody walks at 1.3 m/s until blocked;
  distribution  desired speeds N(1.34, 0.26²) m/s truncated to ±3 sd (Helbing & Molnár 1995);
  weidmann      the same, times Weidmann's (1993) factor φ(ρ) at the local density ρ counted
                within R = 1 m (γ = 1.913 /m², ρ_max = 5.4 /m²).
The flow J (persons/s) is measured in the steady part, from the 10th to the 90th percentile of
the passages (a person passes when removed, 1 m past the door line): J = (n90 − n10)/(t90 − t10).
A run in which 90 % are not out by T counts as clogged. The specific flow J_s = J/b is plotted
against the width b beside the bottleneck experiments (approximate bands, see docs/abm.md).

Usage: crowd_flow.py MOREAU OUT_DIR [--widths B ...] [--seeds N] [--models M ...] [--jobs J]
                     [--plot-only]
Writes OUT_DIR/crowd_flow.csv (one row per run) and OUT_DIR/crowd_flow.png.
"""
import argparse
import concurrent.futures
import csv
import math
import pathlib
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = pathlib.Path(__file__).parent
COUNT = 200
T_MAX = 300.0
LITERATURE = ["forces.propulsion_speed=1.34", "forces.propulsion_speed_sd=0.26"]
MODELS = {
    "constant": [],
    "distribution": LITERATURE,
    "weidmann": LITERATURE + ["forces.density_radius=1.0"],
}
LABELS = {
    "constant": "constant speed 1.3 m/s",
    "distribution": "desired speeds N(1.34, 0.26) m/s",
    "weidmann": "desired speeds × Weidmann φ(ρ)",
}
WEIDMANN = (1.34, 1.913, 5.4)  # free speed (m/s), γ and ρ_max (persons/m²)


def steady_flow(population_csv, count):
    """J between the 10th and the 90th percentile of the passages; NaN when 90 % are not out."""
    rows = list(csv.DictReader(open(population_csv)))
    t = [float(r["t"]) for r in rows]
    out = [int(r["removals"]) for r in rows]

    def first(n):
        return next((ti for ti, o in zip(t, out) if o >= n), None)
    lo, hi = math.ceil(0.1 * count), math.ceil(0.9 * count)
    if first(hi) is None:
        return float("nan")
    return (hi - lo) / (first(hi) - first(lo))


def run_one(moreau, out, model, width, seed):
    run = out / f"{model}_b{width:g}_s{seed}"
    sets = [f"room.door_width={width}", f"problem.seed={seed}", f"problem.T={T_MAX}",
            "population.record_every=1", "output.hdf5=false", "output.vtu=false",
            "output.snapshots=false"] + MODELS[model]
    cmd = [moreau, "run", str(HERE / "crowd_exit.toml"), "--out", str(run)]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, capture_output=True)
    return model, width, seed, steady_flow(run / "population.csv", COUNT)


def weidmann_capacity():
    """The largest specific flow ρ v(ρ) of Weidmann's fundamental diagram (persons/(m s))."""
    v0, gamma, rho_max = WEIDMANN
    rhos = [rho_max * i / 10000 for i in range(1, 10000)]
    return max(r * v0 * (1 - math.exp(-gamma * (1 / r - 1 / rho_max))) for r in rhos)


def plot(rows, path):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    # Approximate ranges of the measured specific flow over the widths each study used.
    ax.fill_between([0.8, 1.2], 1.6, 2.0, color="0.6", alpha=0.45, lw=0,
                    label="Seyfried et al. 2009, b 0.8–1.2 m (≈1.6–2.0)")
    ax.fill_between([0.4, 1.6], 1.5, 2.0, color="0.8", alpha=0.45, lw=0,
                    label="Kretz et al. 2006, b 0.4–1.6 m (≈1.5–2)")
    ax.axhline(weidmann_capacity(), color="k", ls=":", lw=1,
               label="max ρ·v(ρ) of Weidmann's diagram")
    for c, model in enumerate(MODELS):
        mine = [r for r in rows if r[0] == model]
        if not mine:
            continue
        widths = sorted({r[1] for r in mine})
        means, sds = [], []
        for b in widths:
            js = [r[3] / b for r in mine if r[1] == b and not math.isnan(r[3])]
            ax.plot([b] * len(js), js, ".", color=f"C{c}", alpha=0.4)
            clogged = sum(1 for r in mine if r[1] == b and math.isnan(r[3]))
            if clogged:
                ax.plot([b + 0.03 * (c - 1)], [0.1], "x", color=f"C{c}", ms=8)
            m = sum(js) / len(js) if js else float("nan")
            means.append(m)
            sds.append(math.sqrt(sum((j - m) ** 2 for j in js) / (len(js) - 1))
                       if len(js) > 1 else 0.0)
        ax.errorbar(widths, means, yerr=sds, fmt="o-", color=f"C{c}", capsize=3,
                    label=LABELS[model])
    ax.set_xlabel("door width b (m)")
    ax.set_ylabel("specific flow J/b (persons / (m s))")
    ax.set_xlim(0.3, 2.6)
    ax.set_ylim(0, 7)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="center right")
    ax.set_title("200 pedestrians, radius 0.25 m; ×: clogged (90 % not out in 300 s)",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=150)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("moreau")
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--widths", type=float, nargs="+", default=[0.8, 1.0, 1.2, 1.6, 2.0, 2.4])
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--models", nargs="+", choices=list(MODELS), default=list(MODELS))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--plot-only", action="store_true", help="redraw from OUT_DIR/crowd_flow.csv")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    if a.plot_only:
        rows = [(r["model"], float(r["door_width"]), int(r["seed"]), float(r["flow"]))
                for r in csv.DictReader(open(a.out / "crowd_flow.csv"))]
        plot(rows, a.out / "crowd_flow.png")
        return
    jobs = [(m, b, s) for m in a.models for b in a.widths for s in range(1, a.seeds + 1)]
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        rows = list(pool.map(lambda j: run_one(a.moreau, a.out, *j), jobs))
    with open(a.out / "crowd_flow.csv", "w") as f:
        f.write("model,door_width,seed,flow,specific_flow\n")
        for m, b, s, j in rows:
            f.write(f"{m},{b:g},{s},{j:.6g},{j / b:.6g}\n")
    for m in a.models:
        for b in a.widths:
            js = [r[3] / b for r in rows if r[0] == m and r[1] == b]
            print(f"{m:13s} b = {b:g} m: J/b = " + ", ".join(f"{j:.2f}" for j in js))
    plot(rows, a.out / "crowd_flow.png")


if __name__ == "__main__":
    main()
