#!/usr/bin/env bash
# Runs every fuzz target for SECONDS, the targets side by side: fuzz/run.sh BUILD_DIR SECONDS
# MOCAP_DATA_DIR
#   (fuzz/run.sh BUILD_DIR SECONDS MOCAP_DATA_DIR TARGET… runs only those targets, one after the
#   other)
#   seeds: fuzz/corpus/<target>/ (committed: hand-made seeds and every past finding), plus the
#   scenario files of examples/ (scenario_fuzz), its sweep files (sweep_fuzz), its gap lists
#   (gaps_fuzz) and the C3D files under 400 kB of MOCAP_DATA_DIR (c3d_fuzz), copied into
#   BUILD_DIR/seeds/<target>/ at run time;
#   working corpus: BUILD_DIR/corpus/<target>/ (grows from run to run);
#   findings: BUILD_DIR/findings/<target>-crash-… (the run then fails).
set -euo pipefail
build=$1
seconds=$2
mocap=$3
shift 3
root=$(cd "$(dirname "$0")/.." && pwd)

mkdir -p "$build/seeds/scenario_fuzz" "$build/seeds/c3d_fuzz" "$build/seeds/sweep_fuzz" \
  "$build/seeds/gaps_fuzz" "$build/findings"
find "$root/examples" -name '*.toml' -exec cp -f {} "$build/seeds/scenario_fuzz/" \;
find "$root/examples/sweeps" -name '*.toml' -exec cp -f {} "$build/seeds/sweep_fuzz/" \;
find "$root/examples/mocap" -name '*.csv' -exec cp -f {} "$build/seeds/gaps_fuzz/" \;
if [ -d "$mocap" ]; then
  find "$mocap" -name '*.c3d' -size -400k -exec cp -f {} "$build/seeds/c3d_fuzz/" \;
fi

# The targets run side by side (one process each), then each one's result is reported.
run_target() {
  local target=$1 max_len
  case $target in
    scenario_fuzz | sweep_fuzz | gaps_fuzz) max_len=16384 ;;
    c3d_fuzz) max_len=131072 ;;
  esac
  mkdir -p "$build/corpus/$target"
  local seeds=("$build/seeds/$target")
  [ -d "$root/fuzz/corpus/$target" ] && seeds+=("$root/fuzz/corpus/$target")
  "$build/$target" -max_total_time="$seconds" -max_len="$max_len" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$build/findings/$target-" \
    "$build/corpus/$target" "${seeds[@]}" > "$build/$target.log" 2>&1
}

# All targets side by side; or, with targets named on the command line, those one after the other.
targets=(scenario_fuzz c3d_fuzz sweep_fuzz gaps_fuzz)
sequential=0
[ $# -gt 0 ] && targets=("$@") && sequential=1
declare -A result
pids=()
for target in "${targets[@]}"; do
  echo "fuzz: $target for ${seconds} s" >&2
  run_target "$target" &
  pids+=($!)
  if [ $sequential = 1 ]; then
    if wait "${pids[-1]}"; then result[$target]=0; else result[$target]=1; fi
  fi
done

status=0
for i in "${!targets[@]}"; do
  target=${targets[$i]}
  if [ $sequential = 0 ]; then
    if wait "${pids[$i]}"; then result[$target]=0; else result[$target]=1; fi
  fi
  if [ "${result[$target]}" != 0 ]; then
    echo "fuzz: $target found a problem (log: $build/$target.log):" >&2
    grep -E 'ERROR|SUMMARY|Test unit written' "$build/$target.log" >&2 || tail -20 "$build/$target.log" >&2
    status=1
  fi
  grep -E '^stat::(number_of_executed_units|new_units_added|peak_rss_mb)' "$build/$target.log" \
    | sed "s/^/fuzz: $target /" >&2 || true
  echo "fuzz: $target corpus $(ls "$build/corpus/$target" | wc -l) files" >&2
done
exit $status
