#!/usr/bin/env bash
# moreau's particle engine side by side with LAMMPS on the same 2D disks (results in
# docs/benchmarks.md, "moreau against LAMMPS"). LAMMPS is a benchmark-only dependency: without
# `lmp` on PATH the script says so and exits 0.
#
#   bench/lammps_compare.sh [MAX_N]     N = 10^4, 10^5, 10^6 up to MAX_N (default 10^6)
#
# Environment: MOREAU (the CLI, default build/release/moreau), PYTHON (default /usr/bin/python3,
# with numpy and h5py), STEPS_PER_L (steps = STEPS_PER_L · L, default 2), REPEATS (runs of each
# engine, interleaved; the fastest is reported; default 1), WORK (scratch folder, default a fresh
# temporary one, removed at the end unless KEEP=1).
#
# Per N, in one run: LAMMPS on 1 and 2 MPI ranks, then `moreau run` with 1 and 2 threads, all from
# the same start (bench/lammps_compare.py). Printed per row: the timed loop in seconds (LAMMPS'
# "Loop time"; moreau's total_seconds, which excludes setup, and the overlap monitor's share, which
# LAMMPS does not do), ns per particle-step, neighbour-list builds, and the max and mean overlap of
# the pairs that overlap after the run with their count, computed from the last frame by the same
# numpy cell grid for both.
set -euo pipefail

if ! command -v lmp >/dev/null 2>&1; then
  echo "skipped: lmp not found (apt-get install lammps)"
  exit 0
fi

MAX_N=${1:-1000000}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
MOREAU=${MOREAU:-$ROOT/build/release/moreau}
PYTHON=${PYTHON:-/usr/bin/python3}
STEPS_PER_L=${STEPS_PER_L:-2}
REPEATS=${REPEATS:-1}
TOOLS=$ROOT/bench/lammps_compare.py

[[ -x $MOREAU ]] || { echo "moreau CLI not found at $MOREAU (build the moreau_cli target)" >&2; exit 1; }

WORK=${WORK:-$(mktemp -d)}
[[ ${KEEP:-0} == 1 ]] || trap 'rm -rf "$WORK"' EXIT
MPIRUN=(mpirun -np 2 --bind-to none --mca mpi_yield_when_idle 1)
[[ $(id -u) == 0 ]] && MPIRUN+=(--allow-run-as-root)
MPIRUN+=(--oversubscribe)
export OMP_NUM_THREADS=1

# The LAMMPS model: overdamped-like soft disks. m dv/dt = F_pair − K x − γ v with γ = 1 and
# m = γ h (velocity relaxes in one step, terminal velocity F/γ as in moreau's mobility 1);
# K x from fix spring/self anchored at the origin (the atoms are moved there while it is
# defined, then back). Soft repulsion E = A (1 + cos(π r / 2r)), stiffness k = π² A / (2r)², with
# k h = 1/2. Skin 0.5 = moreau's skin_factor 1 · r; the list is checked every step.
lammps_input() {
  cat <<EOF
units lj
dimension 2
atom_style atomic
boundary f f p
read_data start.data
mass 1 $H
fix start all store/state 0 x y
variable x0 atom f_start[1]
variable y0 atom f_start[2]
set group all x 0.0
set group all y 0.0
fix trap all spring/self 1.0 xy
set group all x v_x0
set group all y v_y0
unfix start
variable vx atom -x
variable vy atom -y
velocity all set v_vx v_vy 0.0
pair_style soft 1.0
pair_coeff * * $SOFT_A
neighbor 0.5 bin
neigh_modify every 1 delay 0 check yes
fix move all nve
fix damp all viscous 1.0
fix plane all enforce2d
timestep $H
thermo $STEPS
run $STEPS
write_dump all custom \${dump} id x y modify format float %.17g
EOF
}

overlap() { "$PYTHON" "$TOOLS" overlap "$1"; }
json_field() { "$PYTHON" -c "import json,sys; print(json.load(open(sys.argv[1]))['$2'])" "$1"; }
ns_per() { "$PYTHON" -c "print(f'{1e9 * $1 / ($STEPS * $N):.1f}')"; }
min() { "$PYTHON" -c "import sys; print(f'{min(map(float, sys.argv[1:])):.4g}')" "$@"; }

# One run of each engine; appends the loop time (and moreau's monitor time) to the lists below.
run_lammps() {  # ranks
  local launcher=()
  (( $1 == 1 )) || launcher=("${MPIRUN[@]}")
  (cd "$dir" && "${launcher[@]}" lmp -in in.disks -var dump "final.$1.dump" -log "log.$1" -screen none)
  loops[lammps$1]+=" $(awk '/^Loop time of/ {print $4}' "$dir/log.$1")"
}
run_moreau() {  # threads
  local out=$dir/moreau_t$1
  rm -rf "$out"
  "$MOREAU" run "$dir/moreau_t$1.toml" --out "$out" >/dev/null
  loops[moreau$1]+=" $(json_field "$out/summary.json" total_seconds)"
  monitors[moreau$1]+=" $(json_field "$out/summary.json" monitor_seconds)"
}
row() {  # engine label, loop seconds, extra loop text, list builds, overlap JSON
  echo "| $N | $1 | $2$3 | $(ns_per "$2") | $4 | $(echo "$5" | "$PYTHON" -c \
    "import json,sys; o=json.load(sys.stdin); \
print(f\"{o['max_overlap']:.3g} | {o['mean_overlap']:.3g} | {o['overlapping_pairs']}\")") |"
}

echo "| N | engine | loop (s) | ns/particle-step | list builds | max overlap | mean overlap | overlapping pairs |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
for n in 10000 100000 1000000; do
  (( n <= MAX_N )) || continue
  dir=$WORK/n$n
  mkdir -p "$dir"
  "$PYTHON" "$TOOLS" start "$n" "$dir" "$STEPS_PER_L" 1 2
  # shellcheck disable=SC1091
  source "$dir/run.env"
  lammps_input >"$dir/in.disks"
  declare -A loops=() monitors=()
  # Interleaved repeats, the fastest of each kept: load from other processes only slows a run.
  for (( r = 0; r < REPEATS; ++r )); do
    for k in 1 2; do run_lammps $k; run_moreau $k; done
  done
  for k in 1 2; do
    row "LAMMPS, $k MPI rank(s)" "$(min ${loops[lammps$k]})" "" \
      "$(awk '/^Neighbor list builds/ {print $5}' "$dir/log.$k")" "$(overlap "$dir/final.$k.dump")"
  done
  for k in 1 2; do
    loop=$(min ${loops[moreau$k]})
    row "moreau, $k thread(s)" "$loop" " (monitor $(min ${monitors[moreau$k]}))" \
      "$(json_field "$dir/moreau_t$k/summary.json" neighbour_list_builds)" \
      "$(overlap "$dir/moreau_t$k/trajectory.h5")"
  done
  unset loops monitors
done
echo "steps = $STEPS_PER_L·L, h = 0.01/L, fastest of $REPEATS; LAMMPS" \
  "$(lmp -h | awk -F' - ' 'NR == 2 {print $2, $3}')"
