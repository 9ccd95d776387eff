#!/usr/bin/python3
"""Figures of an agent-based run of `moreau run` (docs/abm.md).

Usage:
  plot_abm.py count OUTPUT_PNG POPULATION_CSV [POPULATION_CSV ...]
      the count per type against time (log scale), one line per type and file
  plot_abm.py snapshot OUTPUT_PNG AGENTS_CSV
      the agents (2D) as disks coloured by generation (an empty room: empty axes)
  plot_abm.py invasion OUTPUT_PNG RUN_DIR [FRONT_CSV]
      a two-type run (examples/abm/invasion.toml): snapshots of the first, a middle and the last
      frame of RUN_DIR/trajectory.h5 coloured by type, and against time the second type's share
      of the cells (RUN_DIR/population.csv), the distance of its farthest cell from the centroid
      of all cells (the invasion front) and that of the farthest cell of all (the tissue's edge);
      FRONT_CSV gets these per frame
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


def front_table(path):
    """Per frame of trajectory.h5 at PATH: t, the count of each of the first two types, the
    second type's area fraction, the farthest second-type and farthest cell's edge from the
    centroid (‖X − X̄‖ + r)."""
    import h5py  # only this figure reads a trajectory

    rows, frames = [], []
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        fail(f"{path}: {e}")
    with f:
        names = [n.decode() if isinstance(n, bytes) else str(n) for n in f.attrs["type_names"]]
        for k, t in enumerate(f["time"][:]):
            n = int(f["count"][k])
            x, r = f["positions"][k, :n, :2], f["radii"][k, :n]
            kind = f["point_data/type"][k, :n]
            edge = np.linalg.norm(x - x.mean(axis=0), axis=1) + r
            area = np.pi * r**2
            second = kind == 1
            rows.append((t, int((kind == 0).sum()), int(second.sum()),
                         area[second].sum() / area.sum(),
                         edge[second].max() if second.any() else 0.0, edge.max()))
            frames.append((t, x, r, kind))
    return names, rows, frames


def draw_types(ax, frame, names, lim):
    t, x, r, kind = frame
    colours = np.array(["#4c72b0", "#c44e52"])[np.minimum(kind, 1)]
    ax.add_collection(PatchCollection([Circle((a, b), c) for (a, b), c in zip(x, r)],
                                      facecolors=colours, linewidths=0))
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    counts = ", ".join(f"{(kind == i).sum()} {name}" for i, name in enumerate(names[:2]))
    ax.set_title(f"t = {t:g}: {counts}", fontsize=9)


def plot_invasion(output, run, front_csv=None):
    names, rows, frames = front_table(f"{run}/trajectory.h5")
    if len(names) < 2 or not frames:
        fail(f"{run}/trajectory.h5: needs two types and a frame")
    header, data = read_csv(f"{run}/population.csv")
    table = np.array(rows)
    lim = max(1.0, table[:, 5].max() + 1)
    fig, axes = plt.subplots(1, 4, figsize=(16, 4.2))
    for ax, k in zip(axes, (0, (2 * len(frames)) // 3, len(frames) - 1)):
        draw_types(ax, frames[k], names, lim)
    ax = axes[3]
    t = data[:, header.index("t")]
    share = data[:, header.index(f"count_{names[1]}")] / np.maximum(data[:, header.index("count")], 1)
    ax.plot(t, share, color="#c44e52", label=f"{names[1]} share of the cells")
    ax.plot(table[:, 0], table[:, 3], "o", ms=3, color="#c44e52", label=f"{names[1]} area fraction")
    ax.set_xlabel("time")
    ax.set_ylabel("fraction")
    ax.set_ylim(0, 1)
    twin = ax.twinx()
    twin.plot(table[:, 0], table[:, 4], "--", color="k", label=f"{names[1]} front")
    twin.plot(table[:, 0], table[:, 5], ":", color="k", label="tissue edge")
    twin.set_ylabel("distance from the centroid")
    lines = ax.get_legend_handles_labels()
    more = twin.get_legend_handles_labels()
    ax.legend(lines[0] + more[0], lines[1] + more[1], fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(output, dpi=110)
    if front_csv:
        with open(front_csv, "w") as f:
            f.write(f"t,count_{names[0]},count_{names[1]},area_fraction_{names[1]},"
                    f"front_{names[1]},edge\n")
            for row in rows:
                f.write(f"{row[0]:g},{row[1]},{row[2]},{row[3]:.4f},{row[4]:.3f},{row[5]:.3f}\n")


def main(argv):
    if len(argv) >= 4 and argv[1] == "count":
        plot_count(argv[2], argv[3:])
    elif len(argv) == 4 and argv[1] == "snapshot":
        plot_snapshot(argv[2], argv[3])
    elif len(argv) in (4, 5) and argv[1] == "invasion":
        plot_invasion(argv[2], argv[3], argv[4] if len(argv) == 5 else None)
    else:
        fail("usage: plot_abm.py count OUT.png POPULATION.csv ... | snapshot OUT.png AGENTS.csv"
             " | invasion OUT.png RUN_DIR [FRONT.csv]")


if __name__ == "__main__":
    main(sys.argv)
