#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds the libFuzzer harnesses (fuzz/) with clang and runs each for SECONDS seconds.
# Usage: scripts/fuzz.sh [SECONDS (default 60)] [TARGET ...]   (targets: job gcode ply stl obj)
# Corpora grow in build-fuzz/corpus/<target>/ (seeded from data/ and fuzz/seeds/, which holds the
# small reproducers of ../shared/repro/hostile/); a finding is written to
# build-fuzz/artifacts/<target>/ and ends the run with a nonzero status. Each run's last status
# line (executions, coverage) is printed.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(job gcode ply stl obj)
out=${FUZZ_DIR:-build-fuzz}
cmake -S fuzz -B "$out" -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build "$out" -j "${JOBS:-$(nproc)}" --target $(printf 'fuzz_%s ' "${targets[@]}")
status=0
for t in "${targets[@]}"; do
  case $t in
    job) seeds=(data/jobs data/studies fuzz/seeds/job) ;;
    gcode) seeds=(data/gcode data/jobs fuzz/seeds/gcode) ;;
    ply | stl | obj) seeds=(data/meshes fuzz/seeds/$t) ;;
    *) echo "unknown fuzz target '$t'" >&2; exit 2 ;;
  esac
  existing=()
  for d in "${seeds[@]}"; do [ -d "$d" ] && existing+=("$PWD/$d"); done
  mkdir -p "$out/corpus/$t" "$out/artifacts/$t" "$out/scratch/$t"
  log="$out/fuzz_$t.log"
  echo "fuzz_$t: ${seconds} s" >&2
  # The job harness resolves G-code and mesh paths relative to its working directory: a scratch one.
  if (cd "$out/scratch/$t" && "$OLDPWD/$out/fuzz_$t" "$OLDPWD/$out/corpus/$t" "${existing[@]}" \
        -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=20 -max_len=65536 -print_final_stats=1 \
        -artifact_prefix="$OLDPWD/$out/artifacts/$t/") >"$log" 2>&1; then
    grep -E '^#[0-9]+ +DONE|stat::number_of_executed_units|cov:' "$log" | tail -n 2 >&2
  else
    status=1
    echo "fuzz_$t FOUND A PROBLEM (log: $log):" >&2
    grep -E 'ERROR|SUMMARY|uncaught|deadly|Test unit written' "$log" | head -n 8 >&2
  fi
done
exit $status
