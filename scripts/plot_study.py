#!/usr/bin/python3
"""Convergence and precision-work figures from a study.csv (paper 000, Fig. 8 and 10).

usage: plot_study.py STUDY_CSV OUTPUT_PNG [TITLE]
Left: error against step size h, with a slope-1 guide. Right: error against total constraint
evaluations (equal work means equal abscissa). Runs that failed (error inf) are left out.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    study_csv, output = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else ""
    series = {}
    with open(study_csv, newline="") as f:
        for row in csv.DictReader(f):
            err = float(row["error"])
            if not math.isfinite(err) or err <= 0:
                continue
            series.setdefault(row["method"], []).append(
                (float(row["h"]), err, float(row["constraint_evaluations"])))
    fig, (ax_h, ax_w) = plt.subplots(1, 2, figsize=(11, 4.3))
    markers = "osd^v<>ph*"
    for k, (label, pts) in enumerate(series.items()):
        pts.sort()
        h = [p[0] for p in pts]
        e = [p[1] for p in pts]
        w = [p[2] for p in pts]
        style = dict(marker=markers[k % len(markers)], ms=4, lw=1.2, label=label)
        ax_h.loglog(h, e, **style)
        ax_w.loglog(w, e, **style)
    all_h = sorted({p[0] for pts in series.values() for p in pts})
    if len(all_h) >= 2 and "pbd" in series:
        h0, e0 = min(series["pbd"])[:2]
        ax_h.loglog(all_h, [e0 * h / h0 for h in all_h], "k:", lw=1, label="order 1")
    ax_h.set_xlabel("step size h")
    ax_h.set_ylabel("error  max_k |x_k - x(t_k)|")
    ax_h.set_title("error vs step size")
    ax_w.set_xlabel("total constraint evaluations (work)")
    ax_w.set_ylabel("error")
    ax_w.set_title("precision-work")
    for ax in (ax_h, ax_w):
        ax.grid(True, which="both", alpha=0.3)
    ax_w.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(output, dpi=120, format="png")


if __name__ == "__main__":
    main()
