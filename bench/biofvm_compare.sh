#!/usr/bin/env bash
# BioFVM's LOD diffusion step against FieldSet::Step on the same 100³ grid, in turns in one run
# (bench/biofvm_compare.cpp; docs/benchmarks.md "Diffusing fields").
#   bench/biofvm_compare.sh BIOFVM_DIR [BUILD_DIR]
# BIOFVM_DIR: a BioFVM source tree (https://github.com/MathCancer/BioFVM, version 1.0.4; not a
# dependency of moreau: without it this benchmark skips). BUILD_DIR: a Release build of moreau
# (default build/bench) holding libmoreau.a. BioFVM is compiled with -O3 -march=native, the most
# favourable flags for it; moreau as built (no -march, an AVX2 copy chosen at run time).
set -euo pipefail
biofvm=${1:-}
build=${2:-build/bench}
if [ -z "$biofvm" ] || [ ! -f "$biofvm/BioFVM.h" ]; then
  echo "biofvm_compare: no BioFVM source tree given (BIOFVM_DIR/BioFVM.h): skipped"
  exit 0
fi
if [ ! -f "$build/libmoreau.a" ]; then
  echo "biofvm_compare: $build/libmoreau.a not found (configure with -DMOREAU_BUILD_BENCH=ON and build 'moreau')" >&2
  exit 2
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for f in vector matlab utilities mesh microenvironment solvers basic_agent agent_container MultiCellDS; do
  g++ -O3 -march=native -fopenmp -std=c++17 -w -c "$biofvm/BioFVM_$f.cpp" -o "$work/$f.o" &
done
g++ -O3 -march=native -fopenmp -std=c++17 -w -c "$biofvm/pugixml.cpp" -o "$work/pugixml.o"
wait
g++ -O2 -std=c++20 -fopenmp -Iinclude -I"$biofvm" bench/biofvm_compare.cpp "$work"/*.o \
  "$build/libmoreau.a" -lfmt $(pkg-config --libs hdf5-serial 2>/dev/null || echo -lhdf5) \
  -o "$work/biofvm_compare"
for threads in 1 2; do
  for substrates in 1 4; do
    "$work/biofvm_compare" "$threads" "$substrates" 40 | if [ "$threads$substrates" = 11 ]; then cat; else tail -1; fi
  done
done
