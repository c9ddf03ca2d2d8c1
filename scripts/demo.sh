#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# make demo: verifies the bundled multi-piece job (a block cut by through-slots into three pieces).
set -euo pipefail
bin=${1:-build/apps/morphmill}
out=${2:-out/demo}
job=data/jobs/through_slots.json
"$bin" info "$job"
echo
set +e
"$bin" verify "$job" --out "$out"
status=$?
set -e
echo
echo "demo: the report is $(cd "$out" && pwd)/report.html (also report.md beside it)"
exit $status
