#!/usr/bin/env bash
# The committed outputs of the agent-based examples that docs/abm.md quotes (its numbers are
# checked against these files by tests/docs/test_abm_numbers.py), and the figures drawn from them:
#   scripts/abm_results.sh MOREAU [--long]        (make abm-results)
# runs into a scratch folder and writes
#   docs/results/abm/<run>_population.csv   the run's population.csv
#   docs/results/abm/<run>_summary.csv      summary.json's counters (key,value; no wall-clock times)
#   docs/results/abm/invasion_front.csv     the invasion front per frame (plot_abm.py invasion)
#   docs/figures/abm_monolayer_count.png, abm_monolayer_snapshot.png, abm_invasion.png
# for the runs monolayer (examples/abm/monolayer.toml, about 1 min on 2 cores), invasion and
# invasion_inhibited (the tumour contact-inhibited like the normal cells; seconds), cell_sorting
# and cell_sorting_equal (every pair at k = 1.25; seconds each). --long also reruns
# examples/abm/cell_sorting.py --seeds 3 (half a minute) and examples/abm/crowd_flow.py --seeds 3
# (about 20 min) for docs/results/cell_sorting.csv, crowd_flow.csv and their figures.
set -euo pipefail
MOREAU=$(realpath "$1")
LONG=${2:-}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
PYTHON=/usr/bin/python3
cd "$ROOT"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
RESULTS=docs/results/abm
mkdir -p "$RESULTS"

run() {  # NAME SCENARIO [--set key=value ...]
  local name=$1 scenario=$2
  shift 2
  "$MOREAU" run "$scenario" "$@" --out "$OUT/$name" > /dev/null
  cp "$OUT/$name/population.csv" "$RESULTS/${name}_population.csv"
  "$PYTHON" - "$OUT/$name/summary.json" > "$RESULTS/${name}_summary.csv" <<'PY'
import json, sys
summary = json.load(open(sys.argv[1]))
print("key,value")
for prefix, part in (("", summary), ("engine.", summary["engine"])):
    for key, value in part.items():
        if not isinstance(value, (dict, list)) and not key.endswith("seconds") and key != "scenario_file":
            print(f"{prefix}{key},{json.dumps(value) if isinstance(value, str) else value}")
PY
}

run monolayer examples/abm/monolayer.toml
run invasion examples/abm/invasion.toml
run invasion_inhibited examples/abm/invasion.toml --set types.tumour.max_contacts=3
run cell_sorting examples/abm/cell_sorting.toml
run cell_sorting_equal examples/abm/cell_sorting.toml \
  --set population.adhesion.dark.dark=1.25 --set population.adhesion.light.light=1.25

"$PYTHON" examples/abm/plot_abm.py count docs/figures/abm_monolayer_count.png "$OUT/monolayer/population.csv"
"$PYTHON" examples/abm/plot_abm.py snapshot docs/figures/abm_monolayer_snapshot.png "$OUT/monolayer/agents.csv"
"$PYTHON" examples/abm/plot_abm.py invasion docs/figures/abm_invasion.png "$OUT/invasion" "$RESULTS/invasion_front.csv"

if [ "$LONG" = "--long" ]; then
  "$PYTHON" examples/abm/cell_sorting.py "$MOREAU" "$OUT/cell_sorting_figure" --seeds 3
  cp "$OUT/cell_sorting_figure/cell_sorting.csv" docs/results/cell_sorting.csv
  cp "$OUT/cell_sorting_figure/cell_sorting.png" docs/figures/abm_cell_sorting.png
  "$PYTHON" examples/abm/crowd_flow.py "$MOREAU" "$OUT/crowd_flow" --seeds 3
  cp "$OUT/crowd_flow/crowd_flow.csv" docs/results/crowd_flow.csv
  cp "$OUT/crowd_flow/crowd_flow.png" docs/figures/crowd_flow.png
fi
echo "abm_results.sh: wrote $RESULTS/ and docs/figures/abm_*.png"
