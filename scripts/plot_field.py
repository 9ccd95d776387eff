#!/usr/bin/python3
"""A field on its grid with the agents on it (Debian's python3 with numpy, matplotlib, h5py).

usage: plot_field.py FIELDS_H5 --out PNG [--field NAME] [--frame F] [--z Z]
                     [--trajectory TRAJECTORY_H5] [--unit UNIT]
  FIELDS_H5     the fields of a run (io/grid_writer.h, docs/io.md: /fields/NAME, /time, and the
                grid in the root attributes dimension, origin, spacing, cells)
  --field       the field to draw (default: the first name in alphabetical order)
  --frame       the frame index, negative from the end (default -1, the last)
  --z           3D: the slice z = Z, drawn as the voxel layer that holds it (default the middle
                of the box); not allowed in 2D
  --trajectory  the particles' trajectory.h5 of the run: its frame at the time nearest the
                field's is drawn over the field, each agent a circle: its radius in 2D, in 3D
                the section of its sphere by the plane z = Z (radius √(r² − d²)), for the agents
                whose centre is within one radius of it
  --unit        the length unit the axes are labelled with (e.g. µm; default none)
The image spans the voxels in scene coordinates (the colour of a voxel is its value), with a
colour bar. Exits with status 2 and a one-line message on bad usage or a bad file.
"""
import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402


class UsageError(Exception):
    pass


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(message)


def read_fields(path, name, frame):
    """(grid dict, field name, time, values of the frame: (n_y, n_x) or (n_z, n_y, n_x))."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise UsageError(f"cannot read {path}: {e}")
    with f:
        if f.attrs.get("format") not in ("moreau-fields", b"moreau-fields"):
            raise UsageError(f"{path}: not a moreau fields file (no format = moreau-fields)")
        names = sorted(f["fields"].keys())
        if not names:
            raise UsageError(f"{path}: no fields")
        name = name or names[0]
        if name not in names:
            raise UsageError(f"{path}: no field {name!r} (fields: {', '.join(names)})")
        times = f["time"][:]
        if not -len(times) <= frame < len(times):
            raise UsageError(f"{path}: frame {frame} out of range ({len(times)} frames)")
        grid = {"dimension": int(f.attrs["dimension"]), "origin": f.attrs["origin"][:],
                "spacing": float(f.attrs["spacing"]), "cells": f.attrs["cells"][:]}
        return grid, name, float(times[frame]), f["fields"][name][frame]


def read_particles(path, time):
    """(time, centres N×k, radii N) of the trajectory frame nearest `time`."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise UsageError(f"cannot read {path}: {e}")
    with f:
        times = f["time"][:]
        if len(times) == 0:
            raise UsageError(f"{path}: no frames")
        i = int(np.argmin(np.abs(times - time)))
        n = int(f["count"][i])
        return float(times[i]), f["positions"][i, :n].astype(float), f["radii"][i, :n]


def slice_layer(grid, values, z):
    """(2D values, z of the slice or None, a description of the slice)."""
    if grid["dimension"] == 2:
        if z is not None:
            raise UsageError("--z is for 3D fields; this one is 2D")
        return values, None, ""
    h, z0, nz = grid["spacing"], grid["origin"][2], int(grid["cells"][2])
    if z is None:
        z = z0 + 0.5 * nz * h
    if not z0 <= z <= z0 + nz * h:
        raise UsageError(f"--z {z} is outside the grid's z range [{z0}, {z0 + nz * h}]")
    layer = min(int(np.floor((z - z0) / h)), nz - 1)
    return values[layer], z, f", z = {z:g} (voxel layer {layer})"


def draw(args):
    grid, name, time, values = read_fields(args.fields, args.field, args.frame)
    image, z, where = slice_layer(grid, values, args.z)
    h, (x0, y0) = grid["spacing"], grid["origin"][:2]
    nx, ny = int(grid["cells"][0]), int(grid["cells"][1])
    x1, y1 = x0 + nx * h, y0 + ny * h
    width = 6.0
    fig, ax = plt.subplots(figsize=(width, max(2.5, width * (y1 - y0) / (x1 - x0))))
    shown = ax.imshow(image, origin="lower", extent=(x0, x1, y0, y1), cmap="viridis",
                      interpolation="nearest")
    fig.colorbar(shown, ax=ax, label=name)
    title = f"{name} at t = {time:g}{where}"
    if args.trajectory:
        p_time, centres, radii = read_particles(args.trajectory, time)
        if z is not None:
            distance = np.abs(centres[:, 2] - z)
            near = distance < radii
            centres, radii = centres[near], np.sqrt(radii[near] ** 2 - distance[near] ** 2)
        ax.add_collection(EllipseCollection(
            2 * radii, 2 * radii, np.zeros(len(radii)), units="xy", offsets=centres[:, :2],
            offset_transform=ax.transData, facecolors="none", edgecolors="white", linewidths=0.8))
        title += f", {len(radii)} agents" + ("" if p_time == time else f" at t = {p_time:g}")
    unit = f" ({args.unit})" if args.unit else ""
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel("x" + unit)
    ax.set_ylabel("y" + unit)
    ax.set_title(title)
    fig.tight_layout()
    try:
        fig.savefig(args.out, dpi=150)
    except OSError as e:
        raise UsageError(f"cannot write {args.out}: {e.strerror}")


def main(argv):
    parser = Parser(prog="plot_field.py", description="A field on its grid with the agents on it.")
    parser.add_argument("fields")
    parser.add_argument("--out", required=True)
    parser.add_argument("--field")
    parser.add_argument("--frame", type=int, default=-1)
    parser.add_argument("--z", type=float)
    parser.add_argument("--trajectory")
    parser.add_argument("--unit", default="")
    try:
        draw(parser.parse_args(argv))
    except UsageError as e:
        print(f"plot_field.py: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
