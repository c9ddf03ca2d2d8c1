#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# make demo: verifies two bundled examples in seconds, each into its own directory under OUT
# (default out/demo): the multi-piece job (a block cut by through-slots into three pieces: the
# generator, the OpenVDB reference and the exact surface) and one CAMotics project (slant_test: a
# tapered cutter, which generator 2 builds as it does every tool of revolution).
# make demo-all (`demo.sh BIN OUT --all`) adds the other three CAMotics projects (heart: two
# programs, a ball nose and a bare T2, the second freeing the heart, so two pieces and a voxel of
# 0.5 to resolve the 1.6 mm kerf at the stock's bottom; vcarve: a V-bit; flower_mold: a flat end
# mill on a dense raster), about five minutes more; docs/camotics.md has their full runs.
# Exit code: 0 when every verdict holds, else the first failing run's code.
set -euo pipefail
bin=${1:-build/apps/morphmill}
out=${2:-out/demo}
all=${3:-}

# name | job | verify options
examples=(
  "through_slots|data/jobs/through_slots.json|"
  "slant_test|data/camotics/slant_test/slant_test.camotics|--voxel 0.25 --samples 20000"
)
if [[ $all == --all ]]; then
  examples+=(
    "heart|data/camotics/heart/heart.camotics|--voxel 0.5 --samples 5000"
    "vcarve|data/camotics/vcarve/vcarve.camotics|--voxel 0.2 --samples 20000"
    "flower_mold|data/camotics/flower_mold/flower_mold.camotics|--voxel 0.6 --samples 20000"
  )
fi

status=0
summary=()
for example in "${examples[@]}"; do
  IFS='|' read -r name job options <<<"$example"
  echo "=== $name: $job"
  "$bin" info "$job"
  echo
  set +e
  # shellcheck disable=SC2086 # the options are words
  "$bin" verify "$job" --output "$out/$name" $options
  code=$?
  set -e
  echo
  summary+=("$(printf '%-14s exit %d  %s/report.html' "$name" "$code" "$(mkdir -p "$out/$name" && cd "$out/$name" && pwd)")")
  if [[ $status -eq 0 && $code -ne 0 ]]; then status=$code; fi
done

echo "demo: one report per example (report.md beside each report.html):"
printf '  %s\n' "${summary[@]}"
exit $status
