#!/usr/bin/python3
"""Figures of particle runs (Debian's python3 with numpy and matplotlib).

usage: plot_particles.py OUTPUT_PNG FRAMES_CSV
         FRAMES_CSV has the header t,i,x,y,r (time, particle id, centre, radius) and holds two
         2D frames: all of them when there are at most four, else the first and the last. Both are drawn
         side by side, every particle a circle to scale coloured by its id, titled with its time
         (like paper 000, Fig. 9).
       plot_particles.py --series OUTPUT_PNG SERIES_CSV XLABEL YLABEL
         SERIES_CSV has a header row and two columns (e.g. t,out); the second is drawn against
         the first as a line (people out against time for a crowd evacuation).
Exits with status 2 and a one-line message on bad usage or a bad file.
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402

FRAME_COLUMNS = ("t", "i", "x", "y", "r")
# Above this many particles, circles are drawn without outlines (the outlines would hide them).
OUTLINE_LIMIT = 5000


class UsageError(Exception):
    pass


def read_csv(path, expected_columns=None):
    """Returns (header names, float array with one row per line)."""
    try:
        with open(path, newline="") as f:
            header = [h.strip() for h in f.readline().strip().split(",")]
            if expected_columns is not None:
                missing = [c for c in expected_columns if c not in header]
                if missing:
                    raise UsageError(f"{path}: header {','.join(header)} lacks {','.join(missing)}")
            data = np.loadtxt(f, delimiter=",", ndmin=2)
    except OSError as e:
        raise UsageError(f"cannot read {path}: {e.strerror}")
    except ValueError as e:
        raise UsageError(f"{path}: {e}")
    if data.size and data.shape[1] != len(header):
        raise UsageError(f"{path}: {data.shape[1]} columns but the header names {len(header)}")
    return header, data


def draw_frame(ax, x, y, r, ids, id_range, limits, title):
    n = len(x)
    collection = EllipseCollection(
        2 * r, 2 * r, np.zeros(n), units="xy", offsets=np.column_stack([x, y]),
        offset_transform=ax.transData, cmap="viridis",
        edgecolors="k" if n <= OUTLINE_LIMIT else "none", linewidths=0.4 if n <= OUTLINE_LIMIT else 0)
    collection.set_array(ids)
    collection.set_clim(*id_range)
    ax.add_collection(collection)
    ax.set_xlim(limits[0], limits[1])
    ax.set_ylim(limits[2], limits[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title(title)


def plot_frames(output, frames_csv):
    header, data = read_csv(frames_csv, FRAME_COLUMNS)
    if data.size == 0:
        raise UsageError(f"{frames_csv}: no particles")
    col = {name: data[:, header.index(name)] for name in FRAME_COLUMNS}
    times = np.unique(col["t"])
    shown = list(times) if len(times) <= 4 else [times[0], times[-1]]
    x, y, r = col["x"], col["y"], col["r"]
    limits = (np.min(x - r), np.max(x + r), np.min(y - r), np.max(y + r))
    pad = 0.02 * max(limits[1] - limits[0], limits[3] - limits[2], 1e-12)
    limits = (limits[0] - pad, limits[1] + pad, limits[2] - pad, limits[3] + pad)
    id_range = (np.min(col["i"]), max(np.max(col["i"]), np.min(col["i"]) + 1))
    fig, axes = plt.subplots(1, len(shown), figsize=(5.5 * len(shown), 5), squeeze=False)
    for ax, t in zip(axes[0], shown):
        sel = col["t"] == t
        draw_frame(ax, x[sel], y[sel], r[sel], col["i"][sel], id_range, limits,
                   f"t = {t:g} ({np.count_nonzero(sel)} particles)")
    fig.tight_layout()
    fig.savefig(output, dpi=150)


def plot_series(output, series_csv, xlabel, ylabel):
    header, data = read_csv(series_csv)
    if len(header) != 2:
        raise UsageError(f"{series_csv}: expected two columns, the header names {len(header)}")
    fig, ax = plt.subplots(figsize=(6, 4))
    if data.size:
        ax.plot(data[:, 0], data[:, 1], "C0-", lw=1.5)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(output, dpi=150)


def main(argv):
    if len(argv) == 6 and argv[1] == "--series":
        plot_series(argv[2], argv[3], argv[4], argv[5])
    elif len(argv) == 3 and not argv[1].startswith("--"):
        plot_frames(argv[1], argv[2])
    else:
        raise UsageError("usage: plot_particles.py OUTPUT_PNG FRAMES_CSV | "
                         "plot_particles.py --series OUTPUT_PNG SERIES_CSV XLABEL YLABEL")


if __name__ == "__main__":
    try:
        main(sys.argv)
    except UsageError as e:
        print(f"plot_particles.py: {e}", file=sys.stderr)
        sys.exit(2)
