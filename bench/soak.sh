#!/usr/bin/env bash
# Soak test (a benchmark, not part of `make test`): 10^5 disks with noise for 10^4 steps
# (examples/disks_1e5.toml with forces.diffusion = 0.1, T = 200, h = 0.02), sampling the resident
# set size (VmRSS of /proc/PID/status) once a second. After the warm-up (the first WARMUP
# fraction of the samples, default 0.1) the RSS must stay within 5 % of its median: the check
# prints the samples' range and exits 1 when it is wider.
#   bench/soak.sh [MOREAU] [OUT_DIR] [--set KEY=VALUE ...]
#   (defaults: build/release/moreau, a temporary folder; further arguments go to `moreau run`,
#   e.g. --set output.hdf5=false to soak the engine without the trajectory writer)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
moreau=${1:-$root/build/release/moreau}
out=${2:-$(mktemp -d)}
shift $(($# < 2 ? $# : 2))
warmup=${WARMUP:-0.1}
samples=$out/rss.csv

"$moreau" run "$root/examples/disks_1e5.toml" --out "$out/run" --set forces.diffusion=0.1 \
  --set problem.T=200.0 --set output.vtu=false "$@" > "$out/run.log" 2>&1 &
pid=$!
start=$(date +%s.%N)
echo "seconds,rss_kib" > "$samples"
while kill -0 "$pid" 2> /dev/null; do
  rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2> /dev/null || true)
  [ -n "$rss" ] && echo "$(awk -v a="$(date +%s.%N)" -v b="$start" 'BEGIN {print a - b}'),$rss" >> "$samples"
  sleep 1
done
wait "$pid"

/usr/bin/python3 - "$samples" "$warmup" <<'PY'
import sys
import numpy as np
data = np.loadtxt(sys.argv[1], delimiter=",", skiprows=1, ndmin=2)
t, rss = data[:, 0], data[:, 1] / 1024.0
steady = rss[int(len(rss) * float(sys.argv[2])):]
median = np.median(steady)
spread = (steady.max() - steady.min()) / median
print(f"soak: {t[-1]:.0f} s, {len(rss)} samples; after warm-up RSS {steady.min():.1f} … "
      f"{steady.max():.1f} MiB (median {median:.1f} MiB, range {100 * spread:.2f} % of it); "
      f"peak {rss.max():.1f} MiB")
sys.exit(0 if spread <= 0.05 else 1)
PY
