#!/usr/bin/python3
"""Time of the ocp fill against recording length and gap count (bench/ocp_fill_bench.cpp).

usage: plot_ocp_scaling.py BENCHMARK_JSON OUTPUT_PNG
BENCHMARK_JSON is ocp_fill_bench's --benchmark_out (format json); the BM_OcpFillScaling runs are
named .../frames:F/gaps:G/...
"""
import json
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    runs = json.load(open(sys.argv[1]))["benchmarks"]
    points = []
    for r in runs:
        m = re.search(r"BM_OcpFillScaling/frames:(\d+)/gaps:(\d+)", r["name"])
        if m:
            points.append((int(m[1]), int(m[2]), r["real_time"] / 1000.0))
    fig, (ax_f, ax_g) = plt.subplots(1, 2, figsize=(9, 3.6))
    by_frames = sorted(p for p in points if p[1] == 10)
    by_gaps = sorted((p for p in points if p[0] == 2000), key=lambda p: p[1])
    ax_f.plot([p[0] for p in by_frames], [p[2] for p in by_frames], "o-")
    ax_f.set_xlabel("recording length (frames at 100 Hz), 10 gaps")
    ax_g.plot([p[1] for p in by_gaps], [p[2] for p in by_gaps], "s-", color="tab:orange")
    ax_g.set_xlabel("gaps of 0.2–0.5 s (2000 frames)")
    for ax in (ax_f, ax_g):
        ax.set_ylabel("wall time (s), 2 threads")
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
    fig.suptitle("ocp fill (40 markers, optimal control on): time grows with the gaps", fontsize=10)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
