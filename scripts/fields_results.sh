#!/usr/bin/env bash
# The committed outputs of the fields examples that docs/fields.md quotes (its numbers are checked
# against these files by tests/docs/test_fields_numbers.py), and their figures:
#   scripts/fields_results.sh MOREAU        (make fields-results; about 4 min on 2 cores)
# runs into a scratch folder and writes to docs/results/fields/
#   spheroid_growth.csv, spheroid_fits.csv, spheroid.png   examples/abm/spheroid_3d.toml per frame
#                                     (count, radius, oxygen at the surface and the centre, rim
#                                     thickness, φ, L_eff, theories) and the growth laws' fits
#   spheroid_oxygen.png               the oxygen through the centre with the cells at the end
#   rim.csv, rim.png                  the rim thickness at R ≈ 8 for uptake rates 50, 100, 200
#   chemotaxis.csv, chemotaxis.png    examples/abm/chemotaxis_2d.toml against χ = 0: mean
#                                     nearest-neighbour distance and clusters per frame
#   chemotaxis_t<T>.png               the attractant with the cells at a few times
set -euo pipefail
MOREAU=$(realpath "$1")
ROOT=$(cd "$(dirname "$0")/.." && pwd)
PYTHON=/usr/bin/python3
cd "$ROOT"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
RESULTS=docs/results/fields
mkdir -p "$RESULTS"
SPHEROID=examples/abm/spheroid_3d.toml
CHEMOTAXIS=examples/abm/chemotaxis_2d.toml
# The spheroid's parameters as its scenario gives them (Δt = the rule step, 5 × 0.02).
PARAMS="lambda=0.5 diffusion=200 c_p=0.3 c_n=0.1 dt=0.1"

"$MOREAU" run "$SPHEROID" --out "$OUT/spheroid" > /dev/null
"$PYTHON" scripts/fields_results.py spheroid "$OUT/spheroid" "$RESULTS/spheroid" $PARAMS uptake=150
"$PYTHON" scripts/plot_field.py "$OUT/spheroid/fields.h5" --out "$RESULTS/spheroid_oxygen.png" \
  --field oxygen --z 0 --trajectory "$OUT/spheroid/trajectory.h5"

RUNS=()
for u in 50 100 200; do
  "$MOREAU" run "$SPHEROID" --set types.cell.oxygen.uptake_rate=$u --out "$OUT/u$u" > /dev/null
  RUNS+=("$OUT/u$u:$u")
done
"$PYTHON" scripts/fields_results.py rim "$RESULTS/rim" 8.0 $PARAMS -- "${RUNS[@]}"

"$MOREAU" run "$CHEMOTAXIS" --out "$OUT/chemotaxis" > /dev/null
"$MOREAU" run "$CHEMOTAXIS" --set types.cell.signal.chemotaxis=0 --out "$OUT/control" > /dev/null
"$PYTHON" scripts/fields_results.py chemotaxis "$RESULTS/chemotaxis" "$OUT/chemotaxis" "$OUT/control"
for frame in 0 4 20; do
  "$PYTHON" scripts/plot_field.py "$OUT/chemotaxis/fields.h5" --field signal --frame $frame \
    --out "$RESULTS/chemotaxis_frame$frame.png" --trajectory "$OUT/chemotaxis/trajectory.h5"
done
echo "fields_results.sh: wrote $RESULTS/"
