#!/usr/bin/python3
"""Each filled gap drawn over the observed samples around it (moreau fill-gaps).

usage: plot_gaps.py FILLED_CSV REPORT_JSON OUTPUT_PNG
FILLED_CSV has columns frame,time,marker,x,y,z (empty x,y,z where still missing; frame is the
file's frame number); REPORT_JSON has "units" and "gaps": [{label, first, last, method, status},
...] with 0-based frames (label: the marker's label, as in the CSV; "marker" is its index). One panel per gap (up to 12: filled gaps first, the
longest first): x, y and z of the gapped marker against time, observed samples as dots,
the filled stretch as a line, the gap shaded. Gaps that were not filled are drawn with their
status in the title.
"""
import csv
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MAX_PANELS = 12


def read_filled(path):
    """marker -> list of (0-based frame, time, (x, y, z) or None). The CSV's frame column holds the
    file's frame numbers, which start at the first frame's number (often 1)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    first = min((int(row["frame"]) for row in rows), default=0)
    series = {}
    for row in rows:
        p = None
        if row["x"] != "":
            p = (float(row["x"]), float(row["y"]), float(row["z"]))
        series.setdefault(row["marker"], []).append((int(row["frame"]) - first,
                                                     float(row["time"]), p))
    return series


def main():
    filled_csv, report_json, output = sys.argv[1], sys.argv[2], sys.argv[3]
    series = read_filled(filled_csv)
    with open(report_json) as f:
        report = json.load(f)
    gaps = sorted(report.get("gaps", []),
                  key=lambda g: (g.get("status") == "filled", g["last"] - g["first"]), reverse=True)
    gaps = gaps[:MAX_PANELS]
    units = report.get("units", "")
    if not gaps:
        fig, ax = plt.subplots(figsize=(6, 2))
        ax.text(0.5, 0.5, "no gaps", ha="center", va="center")
        ax.axis("off")
        fig.savefig(output, dpi=110)
        return
    cols = min(3, len(gaps))
    rows = math.ceil(len(gaps) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.0 * rows), squeeze=False)
    colours = ("tab:red", "tab:green", "tab:blue")
    for ax, gap in zip(axes.flat, gaps):
        samples = series[gap["label"]]
        length = gap["last"] - gap["first"] + 1
        pad = max(10, length)
        lo, hi = gap["first"] - pad, gap["last"] + pad
        window = [s for s in samples if lo <= s[0] <= hi]
        inside = [s for s in window if gap["first"] <= s[0] <= gap["last"] and s[2] is not None]
        outside = [s for s in window if not (gap["first"] <= s[0] <= gap["last"]) and s[2]]
        for c, colour in enumerate(colours):
            ax.plot([s[1] for s in outside], [s[2][c] for s in outside], ".", ms=3, color=colour,
                    label="xyz"[c] + " observed")
            if inside:
                ax.plot([s[1] for s in inside], [s[2][c] for s in inside], "-", lw=1.6,
                        color=colour, alpha=0.8)
        t = [s[1] for s in samples if gap["first"] <= s[0] <= gap["last"]]
        if t:
            ax.axvspan(t[0], t[-1], color="0.85", zorder=0)
        ax.set_title(f'{gap["label"]}: frames {gap["first"]}–{gap["last"]}, '
                     f'{gap.get("method", "")} ({gap.get("status", "")})', fontsize=8)
        ax.set_xlabel("time (s)", fontsize=8)
        ax.set_ylabel(f"position ({units})" if units else "position", fontsize=8)
        ax.tick_params(labelsize=7)
    for ax in list(axes.flat)[len(gaps):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=7, loc="best")
    fig.suptitle("filled gaps (lines, shaded) over the observed samples (dots)", fontsize=10)
    fig.tight_layout()
    fig.savefig(output, dpi=110)


if __name__ == "__main__":
    main()
