#!/usr/bin/python3
"""Figures of an agent-based run of `moreau run` (docs/abm.md).

Usage:
  plot_abm.py count OUTPUT_PNG POPULATION_CSV [POPULATION_CSV ...]
      the count per type against time (log scale), one line per type and file
  plot_abm.py snapshot OUTPUT_PNG AGENTS_CSV
      the agents (2D) as disks coloured by generation (an empty room: empty axes)
Both draw empty inputs (no agents, no rows) as empty axes. Exits with status 2 and a one-line message on bad usage or a bad file.
"""
import sys
import warnings

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402


def fail(message):
    print(f"plot_abm.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_csv(path):
    try:
        with open(path) as f:
            header = f.readline().strip().split(",")
        with warnings.catch_warnings():  # a header without rows is an empty table, not a warning
            warnings.simplefilter("ignore", UserWarning)
            data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except (OSError, ValueError) as e:
        fail(f"{path}: {e}")
    if data.size == 0:
        data = np.zeros((0, len(header)))
    if data.shape[1] != len(header):
        fail(f"{path}: {data.shape[1]} columns, but the header names {len(header)}")
    return header, data


def plot_count(output, paths):
    fig, ax = plt.subplots(figsize=(6, 4))
    for path in paths:
        header, data = read_csv(path)
        if "t" not in header:
            fail(f"{path}: no column t")
        t = data[:, header.index("t")]
        for i, name in enumerate(header):
            if name.startswith("count_"):
                ax.semilogy(t, np.maximum(data[:, i], 0.5), lw=1.5, label=name[6:])
    ax.set_xlabel("time")
    ax.set_ylabel("agents")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(output, dpi=150)


def plot_snapshot(output, path):
    header, data = read_csv(path)
    if "z" in header:
        fail("the snapshot is 2D only")
    if any(c not in header for c in ("x", "y", "r", "generation")):
        fail(f"{path}: needs the columns x, y, r and generation")
    x, y, r = (data[:, header.index(c)] for c in ("x", "y", "r"))
    generation = data[:, header.index("generation")]
    fig, ax = plt.subplots(figsize=(7, 6))
    disks = PatchCollection([Circle((a, b), c) for a, b, c in zip(x, y, r)], cmap="viridis",
                            linewidths=0)
    disks.set_array(generation)
    ax.add_collection(disks)
    if len(x) > 0:
        ax.set_xlim(x.min() - 1, x.max() + 1)
        ax.set_ylim(y.min() - 1, y.max() + 1)
    ax.set_aspect("equal")
    fig.colorbar(disks, ax=ax, label="generation")
    ax.set_title(f"{len(x)} agents")
    fig.tight_layout()
    fig.savefig(output, dpi=150)


def main(argv):
    if len(argv) >= 4 and argv[1] == "count":
        plot_count(argv[2], argv[3:])
    elif len(argv) == 4 and argv[1] == "snapshot":
        plot_snapshot(argv[2], argv[3])
    else:
        fail("usage: plot_abm.py count OUT.png POPULATION.csv ... | snapshot OUT.png AGENTS.csv")


if __name__ == "__main__":
    main(sys.argv)
