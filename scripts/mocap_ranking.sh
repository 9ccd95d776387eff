#!/usr/bin/env bash
# The committed evaluation that chooses fill-gaps' default method (docs/mocap.md, "Which method is
# the default"): every method on every shared recording that evaluate-gaps reads, gaps of 0.5, 1
# and 2 s (the longest dropped while they do not fit in the recording's complete part), one marker
# hidden and a segment of three, 20 seeded trials per cell, the same settings for every file. Writes docs/results/mocap/ranking/<recording>_K<k>.json (each
# run's summary.json) and then ranking.csv and ranking.png (scripts/mocap_ranking.py).
#
#   scripts/mocap_ranking.sh MOREAU [DATA]     (about 20 minutes on 2 cores)
#   RECORDINGS="Gait" scripts/mocap_ranking.sh MOREAU   (some recordings again)
set -euo pipefail
MOREAU=${1:?usage: scripts/mocap_ranking.sh MOREAU [DATA]}
DATA=${2:-../shared/data/mocap}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DEST=$ROOT/docs/results/mocap/ranking
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
mkdir -p "$DEST"
. "$ROOT/scripts/mocap_fitting.sh"
RECORDINGS=${RECORDINGS:-Qualisys upper_body_25hz Vicon Eb015pi standing_bts PlugInC3D Gait}
for recording in $RECORDINGS; do
  for k in 1 3; do
    echo "$recording K=$k" >&2
    evaluate_fitting "$MOREAU" "$DATA/$recording.c3d" "$WORK/$recording-$k" \
      "0.5,1.0,2.0 0.5,1.0 0.5" --trials 20 --seed 1 --markers-per-gap "$k"
    cp "$WORK/$recording-$k/summary.json" "$DEST/${recording}_K$k.json"
  done
done
/usr/bin/python3 "$ROOT/scripts/mocap_ranking.py" "$DEST"
