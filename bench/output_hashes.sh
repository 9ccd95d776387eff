#!/usr/bin/env bash
# The bits of every command's outputs: runs a fixed set of examples with the tool MOREAU into
# DIR and prints "sha256  file" for every CSV (without its wall-clock columns), and "positions_hash  run" from each summary.json
# that has one. Two builds agree bit for bit when their listings are equal:
#   bench/output_hashes.sh build/a/moreau /tmp/a > a.txt; bench/output_hashes.sh build/b/moreau /tmp/b > b.txt
#   diff a.txt b.txt
# Runs in a few minutes on 2 cores (MOCAP_DATA: the recordings, ../shared/data/mocap).
set -euo pipefail
MOREAU=$(realpath "$1")
DIR=$2
DATA=${MOCAP_DATA:-$(dirname "$0")/../../shared/data/mocap}
cd "$(dirname "$0")/.."
rm -rf "$DIR" && mkdir -p "$DIR"
run() { local name=$1; shift; "$MOREAU" "$@" --out "$DIR/$name" > /dev/null 2>&1 || echo "exit $? $name"; }
for s in sliding sliding_d5 disks crowd packing3d disks_1e4; do run "run_$s" run "examples/$s.toml"; done
for s in monolayer invasion crowd_exit; do run "abm_$s" run "examples/abm/$s.toml"; done
run run_disks_2threads run examples/disks_1e4.toml --set solver.threads=2
run study_sliding study examples/sliding.toml --methods pbd,pngs,pgs,penalty:100 --h 0.1,0.05,0.025
run study_disks study examples/disks.toml --methods pbd,pngs --h 0.0078125,0.00390625
for s in oscillator_1d arm_2d network_2d; do run "control_$s" control "examples/control/$s.toml"; done
run fill_vicon fill-gaps "$DATA/Vicon.c3d"
run fill_qualisys_rigid fill-gaps "$DATA/Qualisys.c3d" --gaps examples/mocap/qualisys_10_gaps.csv --method rigid
run fill_vicon_prior fill-gaps "$DATA/Vicon.c3d" --set ocp.optimal_control=false
run evaluate_qualisys evaluate-gaps "$DATA/Qualisys.c3d" --gap-seconds 0.1,0.5 --trials 4 --seed 1
run sweep_evacuation sweep examples/sweeps/evacuation.toml
# Each CSV without its *_seconds / total_seconds columns (wall-clock times).
find "$DIR" -name '*.csv' -not -path '*/.moreau-*' | sort | while read -r f; do
  h=$(/usr/bin/python3 -c '
import csv, hashlib, sys
rows = list(csv.reader(open(sys.argv[1])))
keep = [i for i, name in enumerate(rows[0]) if not name.endswith("seconds")] if rows else []
text = "\n".join(",".join(r[i] for i in keep if i < len(r)) for r in rows)
print(hashlib.sha256(text.encode()).hexdigest()[:16])' "$f")
  echo "$h  ${f#"$DIR"/}"
done
find "$DIR" -name summary.json | sort | while read -r f; do
  h=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1])).get("positions_hash", ""))' "$f")
  [ -n "$h" ] && echo "$h  positions ${f#"$DIR"/}"
done
exit 0
