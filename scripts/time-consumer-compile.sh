#!/usr/bin/env bash
# Compile time of a C++ consumer of setbound, header-only against compiled library
# (docs/cpp_usage.md "Compile times"): wall time of `g++ -std=c++17 -O2 -c FILE`, the median of
# RUNS runs (RUNS_SLOW for the header-only umbrella-header files, which take minutes each).
# Usage: bash scripts/time-consumer-compile.sh   [RUNS=3 RUNS_SLOW=1 CXX=g++]
set -euo pipefail
cd "$(dirname "$0")/.."
CXX="${CXX:-g++}"
RUNS="${RUNS:-3}"
RUNS_SLOW="${RUNS_SLOW:-1}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
flags=(-std=c++17 -O2 -Iinclude -I/usr/include/eigen3 -c -o "$tmp/out.o")

median() { sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
time_one() {  # runs file extra-flags...
  local runs=$1 file=$2; shift 2
  for _ in $(seq "$runs"); do
    local t0 t1
    t0=$(date +%s.%N)
    "$CXX" "${flags[@]}" "$@" "$file"
    t1=$(date +%s.%N)
    echo "$t1 - $t0" | bc
  done | median
}

printf '%-45s %14s %14s %8s\n' file header-only compiled ratio
for file in examples/cpp_consumer/main.cpp examples/cpp_consumer/quickstart.cpp; do
  runs_h=$RUNS
  grep -q 'setbound/setbound.hpp' "$file" && runs_h=$RUNS_SLOW
  h=$(time_one "$runs_h" "$file")
  s=$(time_one "$RUNS" "$file" -DSETBOUND_SEPARATE_COMPILATION)
  printf '%-45s %12.1f s %12.1f s %7.0fx\n' "$file" "$h" "$s" "$(echo "$h / $s" | bc -l)"
done
echo "($(date -u +%F), $(nproc) cores, $("$CXX" --version | head -1); header-only: median of $RUNS runs, $RUNS_SLOW for umbrella-header files; compiled: $RUNS)"
