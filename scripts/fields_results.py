#!/usr/bin/python3
"""Measurements and figures of the fields examples (docs/fields.md), from runs of `moreau run`.

usage: fields_results.py spheroid RUN CSV_PREFIX PNG           one spheroid run: per frame
       fields_results.py rim CSV PNG RUN...                    rim thickness against L
       fields_results.py chemotaxis CSV PNG RUN CONTROL        aggregation against the control
(Debian's python3 with numpy, matplotlib, h5py.) Called by scripts/fields_results.sh.
"""
import csv
import math
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

try:
    import tomllib
except ImportError:  # Python < 3.11
    import tomli as tomllib


def frames(run):
    """Yield (time, centres N×k, type index N, field values, grid) per frame of RUN."""
    with h5py.File(f"{run}/trajectory.h5", "r") as t, h5py.File(f"{run}/fields.h5", "r") as f:
        names = sorted(f["fields"].keys())
        grid = {"origin": f.attrs["origin"][:], "spacing": float(f.attrs["spacing"]),
                "cells": f.attrs["cells"][:]}
        for i, time in enumerate(t["time"][:]):
            n = int(t["count"][i])
            yield (float(time), t["positions"][i, :n], t["point_data/type"][i, :n],
                   {name: f["fields"][name][i] for name in names}, grid)


def voxel_centres(grid, shape):
    """Coordinates of the voxel centres, one array per axis in (z, y, x) order of `shape`."""
    h, o = grid["spacing"], grid["origin"]
    axes = [o[a] + h * (np.arange(shape[::-1][a]) + 0.5) for a in range(len(shape))]
    return np.meshgrid(*axes[::-1], indexing="ij")[::-1]  # x, y[, z] arrays of `shape`


def scenario_value(run, *keys):
    """A value of the run's scenario as summary.json echoes it."""
    import json
    node = json.load(open(f"{run}/summary.json"))["scenario"]
    for k in keys:
        node = node[k]
    return node


def radial_mean(r, values, edges):
    """Mean of `values` over the shells edges[i] ≤ r < edges[i+1] (NaN where a shell is empty)."""
    index = np.digitize(r.ravel(), edges) - 1
    inside = (index >= 0) & (index < len(edges) - 1)
    total = np.bincount(index[inside], values.ravel()[inside], len(edges) - 1)
    count = np.bincount(index[inside], None, len(edges) - 1)
    with np.errstate(invalid="ignore"):
        return total / count


def crossing(x, y, level):
    """The largest x at which the profile y(x) (increasing outward) falls below `level`,
    by linear interpolation between the samples; NaN when it never does."""
    below = np.nonzero(y < level)[0]
    if len(below) == 0 or below[-1] + 1 >= len(y):
        return math.nan
    i = below[-1]
    return x[i] + (level - y[i]) * (x[i + 1] - x[i]) / (y[i + 1] - y[i])


def sphere_rim(R, L, c_s, c_p):
    """Rim thickness W of a uniformly consuming sphere of radius R: the depth at which the
    profile c(r) = c_s (R/r) sinh(r/L) / sinh(R/L) falls to c_p (bisection); NaN if it never
    does (the whole sphere above c_p)."""
    def c(r):
        return c_s * (R / r) * math.exp(r / L - R / L) * (1 - math.exp(-2 * r / L)) / (
            1 - math.exp(-2 * R / L))
    if c(1e-9 * R) >= c_p:
        return math.nan
    lo, hi = 1e-9 * R, R
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if c(mid) < c_p else (lo, mid)
    return R - 0.5 * (lo + hi)


def spheroid_frame(time, x, types, oxygen, grid, uptake, diffusion, c_p, c_n):
    """The measures of one frame of a spheroid run (a dict; module docstring of docs/fields.md)."""
    centre = x.mean(axis=0)
    d = np.linalg.norm(x - centre, axis=1)
    R = math.sqrt(5.0 / 3.0 * np.mean(d ** 2))  # the radius of the uniform ball of this Rg
    xs = voxel_centres(grid, oxygen.shape)
    r_vox = np.sqrt(sum((xs[a] - centre[a]) ** 2 for a in range(3)))
    edges = np.arange(0.0, r_vox.max(), 0.5)
    mids = 0.5 * (edges[1:] + edges[:-1])
    profile = radial_mean(r_vox, oxygen, edges)
    ok = ~np.isnan(profile)
    mids, profile = mids[ok], profile[ok]
    c_s = float(np.interp(R, mids, profile))
    r_p = crossing(mids, profile, c_p)
    r_n = crossing(mids, profile, c_n)
    W = R - r_p if not math.isnan(r_p) else math.nan
    # Consumers' volume fraction in the consuming shell [R − W − 1, R − 1] (φ of L_eff).
    volume = 4.0 / 3.0 * math.pi * 0.5 ** 3
    inner = max((R - W - 1) if not math.isnan(W) else 0.0, 0.0)
    outer = R - 1
    consumers = (types == 0) & (d >= inner) & (d < outer)
    phi = consumers.sum() * volume / (4.0 / 3.0 * math.pi * (outer ** 3 - inner ** 3)) \
        if outer > inner else math.nan
    row = {"t": time, "count": len(x), "necrotic": int((types == 1).sum()), "R": R,
           "c_surface": c_s, "c_centre": float(profile[0]), "r_p": r_p, "r_n": r_n, "W": W,
           "phi": phi}
    L = math.sqrt(diffusion / (uptake * phi)) if phi > 0 else math.nan
    row["L_eff"] = L
    row["W_thick"] = L * math.log(c_s / c_p) if c_s > c_p else math.nan
    row["W_sphere"] = sphere_rim(R, L, c_s, c_p) if c_s > c_p and not math.isnan(L) else math.nan
    # Where the living and the necrotic cells are: the necrotic core inside the rim.
    row["mean_r_cell"] = float(d[types == 0].mean())
    row["mean_r_necrotic"] = float(d[types == 1].mean()) if (types == 1).any() else math.nan
    return row, (mids, profile)


def nearest_neighbour_distance(x, box):
    """Mean distance from each agent to its nearest one, minimum image in the periodic box."""
    d = x[:, None, :] - x[None, :, :]
    d -= box * np.round(d / box)
    r = np.sqrt((d ** 2).sum(axis=2))
    np.fill_diagonal(r, np.inf)
    return float(r.min(axis=1).mean())


def clusters(x, box, link):
    """Number of groups of agents linked by centre distances ≤ link (minimum image), and the
    fraction of the agents in the largest one."""
    d = x[:, None, :] - x[None, :, :]
    d -= box * np.round(d / box)
    near = (d ** 2).sum(axis=2) <= link ** 2
    label = -np.ones(len(x), dtype=int)
    sizes = []
    for start in range(len(x)):
        if label[start] >= 0:
            continue
        label[start], stack, size = len(sizes), [start], 0
        while stack:
            i = stack.pop()
            size += 1
            for j in np.nonzero(near[i] & (label < 0))[0]:
                label[j] = len(sizes)
                stack.append(j)
        sizes.append(size)
    return len(sizes), max(sizes) / len(x)


def aggregation(run):
    """Rows (t, mean nearest-neighbour distance, clusters, largest fraction) per frame of RUN."""
    with h5py.File(f"{run}/trajectory.h5", "r") as t:
        lo = np.array(scenario_value(run, "domain", "lo"))
        box = np.array(scenario_value(run, "domain", "hi")) - lo
        rows = []
        for i, time in enumerate(t["time"][:]):
            x = t["positions"][i, :int(t["count"][i])]
            n, largest = clusters(x, box, 1.5)
            rows.append((float(time), nearest_neighbour_distance(x, box), n, largest))
    return rows


def decay_length(mids, profile, lo, hi):
    """L of the profile c ∝ sinh(r/L)/r ≈ e^{r/L}/r over [lo, hi]: the inverse slope of a
    least-squares line through ln(c r)."""
    keep = (mids >= lo) & (mids <= hi) & (profile > 0)
    if keep.sum() < 2:
        return math.nan
    slope = np.polyfit(mids[keep], np.log(profile[keep] * mids[keep]), 1)[0]
    return 1.0 / slope if slope > 0 else math.nan


def spheroid_rows(run, p):
    """The measures of every frame of a spheroid run (p: lambda, uptake, diffusion, c_p, c_n),
    and the radial profile of the last frame."""
    rows, profile = [], None
    for time, x, types, fields, grid in frames(run):
        if len(x) < 2:
            continue
        row, profile = spheroid_frame(time, x, types, fields["oxygen"], grid, p["uptake"],
                                      p["diffusion"], p["c_p"], p["c_n"])
        row["L_fit"] = decay_length(*profile, row["r_p"] - 1, row["R"]) \
            if not math.isnan(row["W"]) else math.nan
        rows.append(row)
    return rows, profile


def growth_fits(rows, p, dt):
    """The exponential rate of the count while every cell is fed, the linear speed of the radius
    once a necrotic core exists, and their theories."""
    fed = [r for r in rows if r["c_centre"] >= p["c_p"] and r["count"] >= 2]
    t = np.array([r["t"] for r in fed])
    rate = np.polyfit(t, np.log([r["count"] for r in fed]), 1)[0]
    rate_R = np.polyfit(t, np.log([r["R"] for r in fed]), 1)[0]
    first_core = next(i for i, r in enumerate(rows) if r["necrotic"] > 0)
    late = rows[first_core:]
    speed = np.polyfit([r["t"] for r in late], [r["R"] for r in late], 1)[0]
    shell = np.mean([(r["R"] ** 3 - (r["R"] - r["W"]) ** 3) / (3 * r["R"] ** 2) for r in late])
    W = np.mean([r["W"] for r in late])
    lam = p["lambda"]
    return {"lambda": lam, "rate_discrete": math.log(2 - math.exp(-lam * dt)) / dt,
            "rate_count": rate, "rate_radius": rate_R, "fed_until": float(t[-1]),
            "fed_count": fed[-1]["count"], "linear_from": late[0]["t"],
            "linear_to": late[-1]["t"], "speed": speed, "W_linear": W,
            "speed_thin": lam * W, "speed_shell": lam * shell,
            "phi_linear": float(np.mean([r["phi"] for r in late]))}


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
        w.writeheader()
        for row in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})


def plot_spheroid(png, rows, fits, profile, p):
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    t = np.array([r["t"] for r in rows])
    n = np.array([r["count"] for r in rows])
    ax[0].semilogy(t, n, "o", ms=3, label="cells")
    ax[0].semilogy(t, [r["necrotic"] or np.nan for r in rows], "s", ms=3, label="necrotic")
    ax[0].semilogy(t, np.exp(fits["lambda"] * t), "k--", lw=1, label=r"$e^{\lambda t}$")
    ax[0].set(xlabel="t", ylabel="count", ylim=(0.8, 2 * n.max()))
    ax[0].legend(fontsize=8)
    R = np.array([r["R"] for r in rows])
    ax[1].plot(t, R, "o", ms=3, label="R (from Rg)")
    t0 = fits["linear_from"]
    R0 = float(np.interp(t0, t, R))
    line = t >= t0 - 3
    ax[1].plot(t[line], R0 + fits["speed_shell"] * (t[line] - t0), "k--", lw=1,
               label=f"λ × shell(W): {fits['speed_shell']:.2f}")
    tf = fits["fed_until"]
    early = t <= t0
    ax[1].plot(t[early], float(np.interp(tf, t, R)) * np.exp(fits["lambda"] / 3 * (t[early] - tf)),
               "k:", lw=1, label=r"$\propto e^{\lambda t/3}$")
    ax[1].set(xlabel="t", ylabel="radius", ylim=(0, 1.1 * R.max()),
              title=f"measured speed {fits['speed']:.2f}")
    ax[1].legend(fontsize=8)
    mids, c = profile
    last = rows[-1]
    ax[2].plot(mids, c, "-", label="oxygen (shell mean)")
    for level, name in ((p["c_p"], "proliferation"), (p["c_n"], "necrosis")):
        ax[2].axhline(level, color="grey", lw=0.8, ls=":")
        ax[2].text(0.2, level + 0.01, name, fontsize=8, color="grey")
    ax[2].axvline(last["R"], color="k", lw=0.8)
    ax[2].axvline(last["r_p"], color="k", lw=0.8, ls="--")
    ax[2].set(xlabel="distance from the centre", ylabel="c", xlim=(0, mids.max()),
              title=f"t = {last['t']:g}: rim W = {last['W']:.2f}")
    ax[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def rim_row(run, p, R_ref):
    """The measures of RUN at the first frame whose radius reaches R_ref."""
    rows, _ = spheroid_rows(run, p)
    row = next((r for r in rows if r["R"] >= R_ref), rows[-1])
    return {"uptake": p["uptake"], "diffusion": p["diffusion"], **row}


def plot_rim(png, rows):
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    L = np.array([r["L_eff"] for r in rows])
    W = np.array([r["W"] for r in rows])
    ax[0].loglog(L, W, "o", label="measured W")
    ax[0].loglog(L, [r["W_sphere"] for r in rows], "s", mfc="none", label="sphere theory")
    ax[0].loglog(L, [r["W_thick"] for r in rows], "^", mfc="none",
                 label="thick limit L ln(c_s/c_p)")
    slope = np.polyfit(np.log(L), np.log(W), 1)[0]
    guide = np.array([L.min(), L.max()])
    ax[0].loglog(guide, W[np.argmin(L)] * guide / L.min(), "k--", lw=1, label="slope 1")
    ax[0].set(xlabel="L_eff = √(D/(u φ))", ylabel="rim thickness W",
              title=f"fitted slope {slope:.2f}")
    ax[0].legend(fontsize=8)
    ax[1].plot(L, [r["L_fit"] for r in rows], "o", label="decay length of the profile")
    ax[1].plot(guide, guide, "k--", lw=1, label="= L_eff")
    ax[1].set(xlabel="L_eff", ylabel="fitted L", xlim=(0, 1.1 * L.max()), ylim=(0, None))
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return slope


def plot_aggregation(png, rows, control):
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8))
    for data, name in ((rows, "chemotaxis"), (control, "control (χ = 0)")):
        t = [r[0] for r in data]
        ax[0].plot(t, [r[1] for r in data], "o-", ms=3, label=name)
        ax[1].plot(t, [r[2] for r in data], "o-", ms=3, label=name)
    ax[0].set(xlabel="t", ylabel="mean nearest-neighbour distance")
    ax[1].set(xlabel="t", ylabel="clusters (links ≤ 1.5)", yscale="log")
    ax[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def parameters(args):
    """key=value arguments as floats."""
    return {k: float(v) for k, v in (a.split("=", 1) for a in args)}


def main(argv):
    command = argv[1]
    if command == "spheroid":  # RUN OUT_PREFIX key=value...
        run, prefix, p = argv[2], argv[3], parameters(argv[4:])
        rows, profile = spheroid_rows(run, p)
        fits = growth_fits(rows, p, p["dt"])
        write_csv(f"{prefix}_growth.csv", rows)
        write_csv(f"{prefix}_fits.csv", [fits])
        plot_spheroid(f"{prefix}.png", rows, fits, profile, p)
    elif command == "rim":  # OUT_PREFIX R_REF key=value... -- RUN:uptake...
        prefix, R_ref = argv[2], float(argv[3])
        split = argv.index("--")
        p = parameters(argv[4:split])
        rows = [rim_row(run, {**p, "uptake": float(u)}, R_ref)
                for run, u in (a.rsplit(":", 1) for a in argv[split + 1:])]
        slope = plot_rim(f"{prefix}.png", rows)
        D_over_u = np.array([r["diffusion"] / r["uptake"] for r in rows])
        exponent = np.polyfit(np.log(D_over_u), np.log([r["W"] for r in rows]), 1)[0]
        for r in rows:
            r["slope_W_L"], r["exponent_W_D_over_u"] = slope, exponent
        write_csv(f"{prefix}.csv", rows)
    elif command == "chemotaxis":  # OUT_PREFIX RUN CONTROL
        prefix, run, control = argv[2:5]
        rows, base = aggregation(run), aggregation(control)
        write_csv(f"{prefix}.csv", [{"t": a[0], "nn_distance": a[1], "clusters": a[2],
                                     "largest_fraction": a[3], "control_nn_distance": b[1],
                                     "control_clusters": b[2], "control_largest_fraction": b[3]}
                                    for a, b in zip(rows, base)])
        plot_aggregation(f"{prefix}.png", rows, base)
    else:
        sys.exit(f"fields_results.py: unknown command {command!r}")


if __name__ == "__main__":
    main(sys.argv)
