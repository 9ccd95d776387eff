#!/usr/bin/env bash
# moreau against IPOPT on the arm model (docs/benchmarks.md, "moreau against
# IPOPT"). IPOPT is a benchmark-only dependency: without it this prints one line and exits 0.
#
#   bench/ipopt_compare.sh [ARGS...]     (default: --check, then N = 256 … 4096)
#   bench/ipopt_compare.sh --window      the gap-filling windows of shared/data/mocap/Vicon.c3d
#                                        (docs/benchmarks.md, "IPOPT on a gap-filling window")
#
# ARGS go to build/release/ipopt_bench (--check, --steps N,N,..., --tol T, --obj-scaling S,
# --verbose; --window [--recording FILE] [--ipopt-seconds S]). Environment: BUILD (the build folder, default build/release). The bench runs in a
# scratch folder, so that no ipopt.opt of the caller's folder changes IPOPT's settings; one thread
# for BLAS and MUMPS.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! pkg-config --exists ipopt 2>/dev/null; then
  echo "skipped: IPOPT not found (apt-get install coinor-libipopt-dev)"
  exit 0
fi
BUILD=${BUILD:-build/release}
cmake --build "$BUILD" --target ipopt_bench >/dev/null
BENCH=$(realpath "$BUILD/ipopt_bench")
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
SCRATCH=$(mktemp -d /tmp/ipopt_compare.XXXXXX)
trap 'rm -rf "$SCRATCH"' EXIT
cd "$SCRATCH"
echo "# $(date -u '+%Y-%m-%d %H:%M:%S UTC'); cores $(getconf _NPROCESSORS_ONLN);" \
     "load average $(cut -d' ' -f1-3 /proc/loadavg); IPOPT $(pkg-config --modversion ipopt)"
if [ $# -gt 0 ]; then
  "$BENCH" "$@"
else
  "$BENCH" --check
  "$BENCH"
fi
