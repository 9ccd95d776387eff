#!/usr/bin/python3
"""A figure of a sweep's table (results.csv of `moreau sweep`): mean and spread over the seeds.

usage: plot_sweep.py RESULTS_CSV OUTPUT_PNG --x KEY --y QUANTITY [--group KEY]
         For every value of --x (and of --group: one line each), the runs with status completed
         and a value of QUANTITY are averaged over the seeds: the line is the mean, the bar the
         standard deviation, the dots the single runs. Runs without a value (e.g. an evacuation
         not finished by the end time) are counted in the legend.
Exits with status 2 and a one-line message on bad usage or a bad file.
"""
import argparse
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


class UsageError(Exception):
    pass


def read_rows(path, keys):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        raise UsageError(f"{path}: cannot read ({e.strerror})")
    if not rows:
        raise UsageError(f"{path}: no rows")
    missing = [k for k in keys if k and k not in rows[0]]
    if missing:
        raise UsageError(f"{path}: no column {', '.join(missing)}")
    return rows


def group_values(rows, x, y, group):
    """{group value: {x value: [y of each completed run]}}, and the runs without a y."""
    values = defaultdict(lambda: defaultdict(list))
    without = defaultdict(int)
    for row in rows:
        g = row[group] if group else ""
        if row["status"] == "completed" and row[y] != "":
            values[g][float(row[x])].append(float(row[y]))
        else:
            without[g] += 1
    return values, without


def draw(values, without, x, y, group, output):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for i, g in enumerate(sorted(values, key=lambda v: float(v) if v else 0.0)):
        colour = f"C{i}"
        xs = sorted(values[g])
        means = [np.mean(values[g][v]) for v in xs]
        spreads = [np.std(values[g][v]) for v in xs]
        label = f"{group} = {g}" if group else y
        if without[g]:
            label += f" ({without[g]} runs without a value)"
        ax.errorbar(xs, means, yerr=spreads, color=colour, marker="o", capsize=3, label=label)
        for v in xs:
            ax.plot([v] * len(values[g][v]), values[g][v], ".", color=colour, alpha=0.3)
    ax.set_xlabel(x)
    ax.set_ylabel(f"{y} (mean ± std over seeds)")
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(output, dpi=120)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("output")
    parser.add_argument("--x", required=True)
    parser.add_argument("--y", required=True)
    parser.add_argument("--group")
    args = parser.parse_args(argv)
    rows = read_rows(args.results, ["status", args.x, args.y, args.group])
    values, without = group_values(rows, args.x, args.y, args.group)
    if not values:
        raise UsageError(f"{args.results}: no completed run has a value of {args.y}")
    draw(values, without, args.x, args.y, args.group, args.output)


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except (UsageError, ValueError) as e:
        print(f"plot_sweep.py: {e}", file=sys.stderr)
        sys.exit(2)
