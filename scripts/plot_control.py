#!/usr/bin/python3
"""Figures of `moreau control` (numpy + matplotlib, Agg backend).

  plot_control.py run OUT.png trajectory.csv controls.csv
      node positions against the reference, and the effective rest lengths.
  plot_control.py study VALUE.png DIFF.png convergence.csv
      thesis Fig. 16 / 22 (discrete value u_N against N, with the Theorem 5.1 bounds when the
      table has them) and Fig. 17 / 23 (max-norm differences of the displacement against N).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    cols = {}
    for i, name in enumerate(header):
        vals = []
        for r in body:
            vals.append(float(r[i]) if i < len(r) and r[i] != "" else np.nan)
        cols[name] = np.array(vals)
    return header, cols


def plot_run(out, trajectory, controls):
    header, tr = read_csv(trajectory)
    _, ct = read_csv(controls)
    t = tr["t"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    ax = axes[0]
    refs = sorted({h.split("_")[0][3:] for h in header if h.startswith("ref") and h.endswith("_x0")},
                  key=int)
    dims = sorted({int(h.split("_x")[1]) for h in header if h.startswith("node") and "_x" in h})
    if len(dims) == 1:
        for k in refs:
            ax.plot(t, tr[f"node{k}_x0"], label=f"node {k}")
            w = tr[f"ref{k}_w"]
            ref = np.where(w > 0, tr[f"ref{k}_x0"], np.nan)
            ax.plot(t, ref, "--", color="k", lw=0.8, label=f"reference {k}")
        ax.set_xlabel("t")
        ax.set_ylabel("position")
    else:
        for k in refs:
            line, = ax.plot(tr[f"node{k}_x0"], tr[f"node{k}_x1"], label=f"node {k}")
            w = tr[f"ref{k}_w"]
            ax.plot(np.where(w > 0, tr[f"ref{k}_x0"], np.nan), np.where(w > 0, tr[f"ref{k}_x1"], np.nan),
                    "--", color=line.get_color(), lw=0.8)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.set_title("paths (dashed: reference)")
    ax.legend(fontsize=7)
    ax = axes[1]
    for name in ct:
        if name.startswith("spring"):
            ax.plot(ct["t"], ct[name], lw=0.9, label=name)
    ax.set_xlabel("t")
    ax.set_ylabel("effective rest length")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def plot_study(value_png, diff_png, table):
    _, c = read_csv(table)
    n = c["steps"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    axes[0].plot(n, c["value"], "*-")
    wide = n.max() / n.min() >= 16
    if wide:
        axes[0].set_xscale("log", base=2)
        axes[1].set_xscale("log", base=2)
    if (c["value"] > 0).all() and c["value"].max() / c["value"].min() > 100:
        axes[0].set_yscale("log")
    axes[0].set_xlabel("N")
    axes[0].set_ylabel(r"discrete value $\bar u_N$")
    axes[0].set_title("value against N")
    ax = axes[1]
    ax.plot(n[:-1], c["value_minus_finest"][:-1], "*", label=r"$\bar u_{N_{max}} - \bar u_N$")
    if np.isfinite(c["bound_lower"]).any():
        ax.plot(n, c["bound_lower"], "-", label="Theorem 5.1 lower bound")
        ax.plot(n, c["bound_upper"], "-", label="Theorem 5.1 upper bound")
        ax.set_yscale("symlog", linthresh=1e-9)
    else:
        d = np.abs(c["value_minus_finest"][:-1])
        d = d[d > 0]
        if d.size:
            ax.set_yscale("symlog", linthresh=d.min())
    ax.set_xlabel("N")
    ax.set_title(r"$u - \bar u_N$ taken relative to the finest N")
    ax.legend(fontsize=8, loc="center right", bbox_to_anchor=(1.0, 0.7))
    fig.tight_layout()
    fig.savefig(value_png, dpi=120)

    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    m = np.isfinite(c["diff_previous"])
    ax.loglog(n[m], c["diff_previous"][m], "o-", label="successive N (coarser grid's nodes)")
    f = c["diff_finest"][:-1] > 0
    ax.loglog(n[:-1][f], c["diff_finest"][:-1][f], "s-", label="against the finest N")
    if m.sum() >= 1:
        n0, d0 = n[m][0], c["diff_previous"][m][0]
        ax.loglog(n[m], d0 * n0 / n[m], "k:", lw=0.8, label="slope −1 (first order)")
        ax.loglog(n[m], d0 * (n0 / n[m]) ** 2, "k--", lw=0.6, label="slope −2")
    ax.set_xlabel("N")
    ax.set_ylabel(r"$\max |x_N - x_{N'}|$")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(diff_png, dpi=120)


def main(argv):
    if len(argv) >= 5 and argv[1] == "run":
        plot_run(argv[2], argv[3], argv[4])
    elif len(argv) >= 5 and argv[1] == "study":
        plot_study(argv[2], argv[3], argv[4])
    else:
        print(__doc__, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
