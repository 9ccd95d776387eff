#!/usr/bin/env bash
# The sweep benchmark of docs/benchmarks.md: 64 short runs on 1 MPI rank against 2,
# measured interleaved (1, 2, 1, 2, …) so that both see the same machine, then the per-run
# overhead of the sweep machinery (the same sweep with runs of 2 steps, one process).
#
#   bench/sweep_speedup.sh [PAIRS]          (default 5 pairs; needs build/release/moreau, mpirun)
#
# Environment: MOREAU (the binary), SWEEP (the sweep file), MPIRUN_OPTS (options for mpirun; by
# default the shared-memory transport only, whose MPI_Init is the cheapest, and no binding).
# Prints, per pair, the wall time of the whole command and total_seconds of summary.json (the
# sweep inside the process), the ratios, and checks that both results.csv are byte-identical.
set -euo pipefail
cd "$(dirname "$0")/.."
PAIRS=${1:-5}
MOREAU=${MOREAU:-build/release/moreau}
SWEEP=${SWEEP:-examples/sweeps/bench_64.toml}
MPIRUN_OPTS=${MPIRUN_OPTS:---mca pml ob1 --mca btl self,vader --bind-to none}
export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive  # one thread per rank: ranks = cores
PY=/usr/bin/python3
OUT=$(mktemp -d /tmp/sweep_speedup.XXXXXX)
trap 'rm -rf "$OUT"' EXIT
ROOT_FLAG=$([ "$(id -u)" = 0 ] && echo --allow-run-as-root || true)

machine() {
  echo "# $(date -u '+%Y-%m-%d %H:%M:%S UTC'); cores $(getconf _NPROCESSORS_ONLN); taskset: $(taskset -p $$ | sed 's/.*: //');" \
       "load average $(cut -d' ' -f1-3 /proc/loadavg)"
}

# One timed sweep on $1 ranks into $2; prints "wall sweep cpu" (cpu: user + system seconds of
# mpirun and the ranks, which a loaded machine inflates far less than the wall time).
timed() {
  # shellcheck disable=SC2086
  /usr/bin/time -f "%e %U %S" -o "$2.time" mpirun $ROOT_FLAG $MPIRUN_OPTS -n "$1" "$MOREAU" sweep \
    "$SWEEP" --out "$2" >/dev/null
  $PY -c 'import json,sys; w,u,s=map(float,open(sys.argv[1]).read().split()[-3:])
print(w, json.load(open(sys.argv[2]))["total_seconds"], round(u+s,3))' "$2.time" "$2/summary.json"
}

machine
echo "# $MOREAU sweep $SWEEP; mpirun $MPIRUN_OPTS"
timed 1 "$OUT/warm" >/dev/null  # page cache, first MPI start
printf '%-5s %28s %28s %18s\n' pair "1 rank: wall (sweep) cpu" "2 ranks: wall (sweep) cpu" \
  "ratio wall (sweep)"
RESULTS=$OUT/pairs.txt
: >"$RESULTS"
for ((i = 1; i <= PAIRS; i++)); do
  rm -rf "$OUT/r1" "$OUT/r2"
  read -r w1 s1 c1 < <(timed 1 "$OUT/r1")
  read -r w2 s2 c2 < <(timed 2 "$OUT/r2")
  cmp -s "$OUT/r1/results.csv" "$OUT/r2/results.csv" || { echo "results.csv differ" >&2; exit 1; }
  echo "$w1 $s1 $c1 $w2 $s2 $c2" >>"$RESULTS"
  $PY -c 'import sys; w1,s1,c1,w2,s2,c2=map(float,sys.argv[2:])
print(f"{sys.argv[1]:<5} {w1:8.2f} s ({s1:6.2f} s) {c1:6.2f} s  {w2:8.2f} s ({s2:6.2f} s) {c2:6.2f} s  {w1/w2:7.2f}× ({s1/s2:.2f}×)")' \
    "$i" "$w1" "$s1" "$c1" "$w2" "$s2" "$c2"
done
$PY - "$RESULTS" <<'PY'
import statistics, sys
rows = [list(map(float, line.split())) for line in open(sys.argv[1])]
def report(what, ratios):
    print(f"{what}: median {statistics.median(ratios):.2f}×, range {min(ratios):.2f}–{max(ratios):.2f}×")
report("speed-up, whole command", [r[0] / r[3] for r in rows])
report("speed-up, inside the sweep", [r[1] / r[4] for r in rows])
extra = [r[5] - r[2] for r in rows]
print(f"CPU of 2 ranks minus 1 rank: median {statistics.median(extra):.2f} s "
      f"(range {min(extra):.2f}–{max(extra):.2f} s)")
PY
# Per-run overhead: runs of 2 steps, one process without MPI, 3 repetitions.
for i in 1 2 3; do
  rm -rf "$OUT/o"
  "$MOREAU" sweep "$SWEEP" --set set.problem.T=0.02 --out "$OUT/o" >/dev/null
  $PY -c 'import json,sys; j=json.load(open(sys.argv[1]))
print("overhead per run (64 runs of 2 steps): %.2f ms; sweep %.3f s" % (1e3*j["overhead_seconds_per_run"], j["total_seconds"]))' "$OUT/o/summary.json"
done
machine
