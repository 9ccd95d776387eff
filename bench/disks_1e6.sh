#!/bin/bash
# examples/disks_1e6.toml end to end through the CLI: `moreau run` with 1 and 2 threads, steps/s
# and the engine's phase times from summary.json (the seconds are the engine's own timers; setup
# is the random start, the initial-state check and the first list build).
#
#   bench/disks_1e6.sh [path/to/moreau] [extra --set options ...]
#
# OpenMP waits as moreau chooses unless OMP_WAIT_POLICY or GOMP_SPINCOUNT is set
# (moreau/common/openmp_wait.h). The output folders are left in a temporary directory, removed at exit.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
moreau=${1:-$here/build/release/moreau}
shift || true
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for threads in 1 2; do
  start=$(date +%s.%N)
  OMP_NUM_THREADS=$threads "$moreau" run "$here/examples/disks_1e6.toml" --out "$tmp/t$threads" \
    "$@" >/dev/null
  end=$(date +%s.%N)
  /usr/bin/python3 - "$tmp/t$threads/summary.json" "$threads" "$start" "$end" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
steps = d["steps"]
total = d["total_seconds"]
line = (f"threads {sys.argv[2]}: wall {float(sys.argv[4]) - float(sys.argv[3]):.2f} s, "
        f"setup {d['setup_seconds']:.2f} s, {steps} steps in {total:.2f} s = "
        f"{steps / total:.1f} steps/s; builds {d['neighbour_list_builds']} "
        f"({1e3 * d['neighbour_seconds'] / max(1, d['neighbour_list_builds']):.1f} ms each)")
shares = ", ".join(f"{k[:-8]} {100 * d[k] / total:.0f} %" for k in
                   ["neighbour_seconds", "sweep_seconds", "force_seconds", "monitor_seconds"])
print(line + "; " + shares + f"; positions_hash {d['positions_hash']}")
PY
done
