#!/usr/bin/python3
"""Flow through the door against its width (docs/abm.md): runs examples/abm/crowd_exit.toml for
several door widths, measures the flow J (persons/s) as the slope of the count of people out
between 20 % and 80 % of the crowd (NaN when the door clogs before 80 % are out), and plots the specific flow J/w against w beside the range
1.5–2 persons/(m·s) reported for bottleneck experiments (Seyfried et al. 2009, Kretz et al. 2006).

Usage: crowd_flow.py MOREAU OUT_DIR [WIDTH ...]   (writes OUT_DIR/crowd_flow.csv and .png)
"""
import csv
import pathlib
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = pathlib.Path(__file__).parent


def flow(population_csv, count):
    rows = list(csv.DictReader(open(population_csv)))
    t = [float(r["t"]) for r in rows]
    out = [int(r["removals"]) for r in rows]

    def first(n):
        return next((ti for ti, o in zip(t, out) if o >= n), None)
    lo, hi = round(0.2 * count), round(0.8 * count)
    if first(hi) is None:  # clogged: the door jammed before 80 % were out
        return float("nan")
    return (hi - lo) / (first(hi) - first(lo))


def main(argv):
    if len(argv) < 3:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        sys.exit(2)
    moreau, out = argv[1], pathlib.Path(argv[2])
    widths = [float(w) for w in argv[3:]] or [0.8, 1.2, 1.6, 2.0, 2.4]
    count = 200
    rows = []
    for w in widths:
        run = out / f"door_{w:g}"
        subprocess.run([moreau, "run", str(HERE / "crowd_exit.toml"), "--out", str(run), "--set",
                        f"room.door_width={w}", "--set", "problem.T=120"], check=True,
                       capture_output=True)
        j = flow(run / "population.csv", count)
        rows.append((w, j, j / w))
        print(f"door {w:g} m: flow {j:.2f} /s, specific flow {j / w:.2f} /(m s)")
    with open(out / "crowd_flow.csv", "w") as f:
        f.write("door_width,flow,specific_flow\n")
        for w, j, js in rows:
            f.write(f"{w:g},{j:.6g},{js:.6g}\n")
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot([r[0] for r in rows], [r[2] for r in rows], "C0o-", label="moreau (PBD crowd)")
    ax.axhspan(1.5, 2.0, color="C1", alpha=0.3,
               label="experiments: 1.5–2 /(m s)\n(Seyfried 2009, Kretz 2006)")
    ax.set_xlabel("door width w (m)")
    ax.set_ylabel("specific flow J/w (persons / (m s))")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "crowd_flow.png", dpi=150)


if __name__ == "__main__":
    main(sys.argv)
