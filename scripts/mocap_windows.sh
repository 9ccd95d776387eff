#!/usr/bin/env bash
# How often the optimal control solves its window: `ocp` alone on every shared recording that
# evaluate-gaps reads, one marker hidden and a segment of three, gaps inside the take, anywhere,
# at its start and at its end, gap lengths 0.2, 0.5, 1 and 2 s (the longest dropped while they do
# not fit), 10 seeded trials per length. Writes docs/results/mocap/ocp_windows.csv: per recording,
# K, placement and gap length, the hidden markers' gaps and how many the optimal control filled
# (the others kept the prior: the window did not converge, or it converged and the guard turned
# it down, counted in rejected_by_guard).
#
#   scripts/mocap_windows.sh MOREAU [DATA]     (about 10 minutes on 2 cores)
set -euo pipefail
MOREAU=${1:?usage: scripts/mocap_windows.sh MOREAU [DATA]}
DATA=${2:-../shared/data/mocap}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
. "$ROOT/scripts/mocap_fitting.sh"
for recording in Qualisys upper_body_25hz Vicon Eb015pi standing_bts PlugInC3D Gait; do
  for k in 1 3; do
    for placement in interior any start end; do
      evaluate_fitting "$MOREAU" "$DATA/$recording.c3d" "$WORK/$recording-$k-$placement" \
        "0.2,0.5,1.0,2.0 0.2,0.5,1.0 0.2,0.5" --trials 10 --seed 2 --markers-per-gap "$k" \
        --placement "$placement" --methods ocp
    done
  done
done
/usr/bin/python3 - "$WORK" "$ROOT/docs/results/mocap/ocp_windows.csv" <<'PY'
import csv, json, pathlib, sys
work, dest = pathlib.Path(sys.argv[1]), sys.argv[2]
with open(dest, "w", newline="") as f:
    w = csv.writer(f, lineterminator="\n")
    w.writerow(["recording", "markers_per_gap", "placement", "gap_seconds", "gaps",
                "optimal_control", "prior", "rejected_by_guard", "unfilled"])
    for path in sorted(work.glob("*/summary.json")):
        recording, k, placement = path.parent.name.rsplit("-", 2)
        for s in json.loads(path.read_text())["statistics"]:
            w.writerow([recording, k, placement, s["gap_seconds"], s["gaps"],
                        s["optimal_control"], s["prior"], s["rejected_by_guard"],
                        s["failed"]])
PY
