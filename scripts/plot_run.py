#!/usr/bin/python3
"""Figure of one `moreau run`.

usage: plot_run.py OUTPUT_PNG TRAJECTORY_CSV KIND [RADIUS]
sliding: the path in the (x0, x1) plane with the unit circle, and the components against t.
disks:   the first and the last frame, disks drawn to scale (paper 000, Fig. 9).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def plot_sliding(rows, ax_path, ax_t):
    t = np.array([float(r["t"]) for r in rows])
    cols = [c for c in rows[0].keys() if c != "t"]
    x = np.array([[float(r[c]) for c in cols] for r in rows])
    s = np.linspace(0, 2 * np.pi, 400)
    ax_path.plot(np.cos(s), np.sin(s), "k:", lw=1, label="unit circle (groove)")
    ax_path.plot(x[:, 0], x[:, 1], "C0-", lw=1.5, label="x0, x1")
    ax_path.set_aspect("equal")
    ax_path.set_xlabel("x0")
    ax_path.set_ylabel("x1")
    ax_path.legend(fontsize=8)
    for j, c in enumerate(cols):
        ax_t.plot(t, x[:, j], label=c)
    ax_t.set_xlabel("t")
    ax_t.legend(fontsize=8)


def plot_disks(rows, radius, axes):
    frames = {}
    for r in rows:
        frames.setdefault(float(r["t"]), []).append((float(r["x"]), float(r["y"])))
    times = sorted(frames)
    pts = np.array([p for f in frames.values() for p in f])
    lo, hi = pts.min(axis=0) - radius, pts.max(axis=0) + radius
    for ax, t in zip(axes, (times[0], times[-1])):
        for (x, y) in frames[t]:
            ax.add_patch(plt.Circle((x, y), radius, fc="C0", ec="k", lw=0.5, alpha=0.8))
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
        ax.set_title(f"t = {t:g}")


def main():
    output, trajectory, kind = sys.argv[1], sys.argv[2], sys.argv[3]
    with open(trajectory, newline="") as f:
        rows = list(csv.DictReader(f))
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.5))
    if kind == "disks":
        plot_disks(rows, float(sys.argv[4]), axes)
    else:
        plot_sliding(rows, *axes)
    fig.tight_layout()
    fig.savefig(output, dpi=120, format="png")


if __name__ == "__main__":
    main()
