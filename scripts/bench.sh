#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Runs every Google Benchmark executable the build produced.
set -euo pipefail
build=${1:-build}
found=0
for b in "$build"/tests/bench/bench_*; do
  [[ -x "$b" && -f "$b" ]] || continue
  found=1
  echo "== $(basename "$b")"
  "$b" --benchmark_counters_tabular=true
done
[[ $found -eq 1 ]] || { echo "bench: no benchmark executables in $build/tests/bench" >&2; exit 1; }
