#!/usr/bin/python3
"""Fill error against gap length, one curve per method (moreau evaluate-gaps).

usage: plot_gap_errors.py EVALUATION_CSV OUTPUT_PNG [TITLE]
EVALUATION_CSV has columns method,gap_frames,trial,marker,first_frame,mean_error,max_error (and
optionally gap_seconds, status, acceleration_error). Per method and gap length: the median of the
per-gap mean error (line) and its 10-90 % band (shaded); failed fills (empty or non-finite error)
are left out and counted in the legend. With an acceleration_error column, a second panel shows
the filtered acceleration error the same way.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def number(text):
    return float(text) if text not in ("", "nan") else math.nan


def read(path, column):
    """{method: {gap_frames: [finite values]}}, {method: failed count}, {gap_frames: seconds}."""
    values, failed, seconds = {}, {}, {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            method, frames = row["method"], int(row["gap_frames"])
            if "gap_seconds" in row and row["gap_seconds"]:
                seconds[frames] = float(row["gap_seconds"])
            value = number(row[column])
            if not math.isfinite(value):
                failed[method] = failed.get(method, 0) + 1
                continue
            values.setdefault(method, {}).setdefault(frames, []).append(value)
    return values, failed, seconds


def panel(ax, values, failed, seconds, ylabel):
    markers = "osd^v<>ph*"
    for k, (method, by_length) in enumerate(values.items()):
        lengths = sorted(by_length)
        x = [seconds.get(n, n) for n in lengths]
        median = [np.median(by_length[n]) for n in lengths]
        p10 = [np.percentile(by_length[n], 10) for n in lengths]
        p90 = [np.percentile(by_length[n], 90) for n in lengths]
        label = method + (f" ({failed[method]} failed)" if failed.get(method) else "")
        line, = ax.plot(x, median, marker=markers[k % len(markers)], ms=4, lw=1.4, label=label)
        ax.fill_between(x, p10, p90, color=line.get_color(), alpha=0.15)
    ax.set_yscale("log")
    ax.set_xlabel("gap length (s)" if seconds else "gap length (frames)")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)


def main():
    path, output = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else ""
    with open(path, newline="") as f:
        columns = next(csv.reader(f), [])
    both = "acceleration_error" in columns
    fig, axes = plt.subplots(1, 2 if both else 1, figsize=(12.0 if both else 6.4, 4.4),
                             squeeze=False)
    panel(axes[0][0], *read(path, "mean_error"), "mean error over the gap (median, 10–90 % band)")
    if both:
        panel(axes[0][1], *read(path, "acceleration_error"),
              "filtered acceleration error, mean over the gap (per s²)")
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(output, dpi=120)


if __name__ == "__main__":
    main()
