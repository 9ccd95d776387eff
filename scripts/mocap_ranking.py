"""The ranking that chooses fill-gaps' default method, from the committed evaluation
(scripts/mocap_ranking.sh writes docs/results/mocap/ranking/<recording>_K<k>.json).

    /usr/bin/python3 scripts/mocap_ranking.py docs/results/mocap/ranking

The rule, the same for every file (docs/mocap.md, "Which method is the default"):
1. cells: every recording × markers hidden (K) × gap length; in each cell a method's value is
   its mean over the trials (position: mean and p90 of the per-gap error; acceleration error;
   partner-distance deviation), divided by the best method's value in that cell;
2. a method's score per measure is the geometric mean of those ratios over the cells (1: best in
   every cell);
3. only a method that filled every gap of every cell may be the default; among those, the ones
   whose position score is within 2 % of the best, then those whose acceleration score is within
   2 % of the best among them, then the fastest (total fill time over the evaluation).
Writes ranking_cells.csv (every cell and method) and ranking.csv (the scores, the eligibility
and the winner) beside the JSON files, and ranking.png.
"""
import csv
import json
import math
import pathlib
import sys

MEASURES = ("mean_error", "p90_error", "acceleration_error", "distance_deviation")
TOLERANCE = 1.02  # "within 2 %"


def cells(folder):
    """({(recording, K, gap_seconds): {method: row}}, {method: fill seconds over every run})
    from the committed summaries."""
    table, seconds = {}, {}
    for path in sorted(pathlib.Path(folder).glob("*_K*.json")):
        recording, k = path.stem.rsplit("_K", 1)
        summary = json.loads(path.read_text())
        for method, time in summary["method_seconds"].items():
            seconds[method] = seconds.get(method, 0.0) + time
        for s in summary["statistics"]:
            row = {"trials": s["trials"], "failed": s["failed"], "mean_error": s["mean_error"],
                   "p90_error": s["p90_error"],
                   "acceleration_error": s["measures"]["acceleration_error"]["mean"],
                   "distance_deviation": s["measures"]["distance_deviation"]["mean"]}
            table.setdefault((recording, int(k), s["gap_seconds"]), {})[s["method"]] = row
    return table, seconds


def scores(table, seconds):
    """{method: {measure score…, "seconds", "unfilled"}}."""
    methods = sorted({m for rows in table.values() for m in rows})
    result = {m: {"seconds": seconds[m], "unfilled": 0, **{k: 0.0 for k in MEASURES}}
              for m in methods}
    for rows in table.values():
        for measure in MEASURES:
            best = min(r[measure] for r in rows.values() if r[measure] is not None)
            for m, r in rows.items():
                value = r[measure] if r[measure] is not None else math.inf
                result[m][measure] += math.log(value / best) / len(table)
        for m, r in rows.items():
            result[m]["unfilled"] += r["failed"]
    for m in methods:
        for measure in MEASURES:
            result[m][measure] = math.exp(result[m][measure])
    return result


def winner(result):
    """The default by the rule of the module's docstring."""
    eligible = [m for m, s in result.items() if s["unfilled"] == 0]
    best = min(result[m]["mean_error"] for m in eligible)
    eligible = [m for m in eligible if result[m]["mean_error"] <= TOLERANCE * best]
    best = min(result[m]["acceleration_error"] for m in eligible)
    eligible = [m for m in eligible if result[m]["acceleration_error"] <= TOLERANCE * best]
    return min(eligible, key=lambda m: result[m]["seconds"])


def write(folder, table, result, chosen):
    folder = pathlib.Path(folder)
    with open(folder / "ranking_cells.csv", "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["recording", "markers_per_gap", "gap_seconds", "method", "trials", "failed",
                    *MEASURES])
        for (recording, k, gap), rows in sorted(table.items()):
            for m, r in sorted(rows.items()):
                w.writerow([recording, k, gap, m, r["trials"], r["failed"],
                            *(f"{r[x]:.6g}" if r[x] is not None else "" for x in MEASURES)])
    with open(folder / "ranking.csv", "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["method", *(f"{x}_score" for x in MEASURES), "seconds", "unfilled",
                    "default"])
        for m, s in sorted(result.items(), key=lambda kv: kv[1]["mean_error"]):
            w.writerow([m, *(f"{s[x]:.4f}" for x in MEASURES), f"{s['seconds']:.3g}",
                        s["unfilled"], "yes" if m == chosen else ""])


def plot(folder, result, chosen):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    methods = sorted(result, key=lambda m: result[m]["mean_error"])
    fig, ax = plt.subplots(figsize=(8, 3.6))
    width = 0.2
    for i, measure in enumerate(MEASURES):
        ax.bar([j + (i - 1.5) * width for j in range(len(methods))],
               [result[m][measure] for m in methods], width, label=measure.replace("_", " "))
    ax.set_xticks(range(len(methods)))
    ax.set_xticklabels([m + (" (default)" if m == chosen else "") for m in methods])
    ax.set_yscale("log")
    ax.axhline(1.0, color="k", lw=0.5)
    ax.set_ylabel("score (1: best in every cell)")
    ax.set_title("Fill methods over every shared recording, K = 1 and 3, gaps 0.5–2 s")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(pathlib.Path(folder) / "ranking.png", dpi=110)


def main(folder):
    table, seconds = cells(folder)
    result = scores(table, seconds)
    chosen = winner(result)
    write(folder, table, result, chosen)
    plot(folder, result, chosen)
    print(f"default: {chosen}")


if __name__ == "__main__":
    main(sys.argv[1])
