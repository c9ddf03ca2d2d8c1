#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The `slurm` test (ctest -L slurm): docs/stress.md's Slurm recipe, as written there, on a real
# one-node Slurm (scripts/slurm-local.sh), against a single-process run of the same campaign:
#   1. the recipe runs and its merge equals the single-process campaign;
#   2. a shard cancelled while running and one cancelled while pending: the merge refuses (exit 4,
#      FAILED), naming both; requeued / resubmitted as the docs say, the running one resumes (its
#      finished cases are kept) and the merge equals the single-process campaign;
#   3. a campaign whose cases fail (--reference-memory-cap 0.001: the reference refuses every case):
#      every task and the merge FAILED with exit 1, the merged summary complete.
# Runs only when MORPHMILL_SLURM_TEST=1 (make test-slurm) or MORPHMILL_REQUIRE_SLURM=1 (.ci/run).
# Exit 0: passed; 1: failed; 77: skipped because not asked, or Slurm cannot run here (not root,
# packages missing, ports taken) -- unless MORPHMILL_REQUIRE_SLURM=1, which makes that a failure.
#
# usage: scripts/slurm-campaign-test.sh MORPHMILL_BINARY [DOCS_FILE] [WORK_DIR]
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
binary=$(realpath "${1:?usage: $0 MORPHMILL_BINARY [DOCS_FILE] [WORK_DIR]}")
docs=$(realpath "${2:-$here/../docs/stress.md}")
work=${3:-$(mktemp -d /tmp/morphmill-slurm-test.XXXXXX)}
mkdir -p "$work"
work=$(cd "$work" && pwd)
state=$work/slurm

skip() {
  if [[ ${MORPHMILL_REQUIRE_SLURM:-0} == 1 ]]; then
    echo "FAIL: Slurm is required here (MORPHMILL_REQUIRE_SLURM=1) but: $*" >&2
    exit 1
  fi
  echo "SKIPPED: the slurm test cannot run here: $*" >&2
  exit 77
}
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
if [[ ${MORPHMILL_SLURM_TEST:-0} != 1 && ${MORPHMILL_REQUIRE_SLURM:-0} != 1 ]]; then
  skip "it starts Slurm daemons as root and takes minutes, so it runs only when asked: make test-slurm (or MORPHMILL_SLURM_TEST=1 ctest -L slurm)"
fi
command -v jq >/dev/null || skip "jq not found (scripts/slurm-local.sh install)"

status=0
"$here/slurm-local.sh" start "$state" || status=$?
if [[ $status -eq 77 ]]; then
  "$here/slurm-local.sh" stop "$state"
  skip "scripts/slurm-local.sh could not start Slurm (reason above)"
elif [[ $status -ne 0 ]]; then
  "$here/slurm-local.sh" stop "$state"
  fail "scripts/slurm-local.sh start exited $status"
fi
trap '"$here/slurm-local.sh" stop "$state"' EXIT
export SLURM_CONF=$state/slurm.conf
export PATH=$(dirname "$binary"):$PATH # the docs: morphmill on PATH when submitting

# The code block that follows the marker <!-- recipe: NAME --> in the docs.
recipe() {
  awk -v marker="<!-- recipe: $1 -->" '
    $0 == marker { found = 1; next }
    found && /^```/ { if (inside) exit; inside = 1; next }
    inside { print }' "$docs"
}
recipe stress.sbatch >"$work/stress.sbatch"
recipe submit >"$work/submit.sh"
[[ -s $work/stress.sbatch && -s $work/submit.sh ]] || fail "$docs: no recipe blocks (<!-- recipe: ... -->)"
grep -q '^exec morphmill stress ' "$work/stress.sbatch" || fail "the recipe's script runs no 'exec morphmill stress'"
cases=$(grep -o -- '--cases [0-9]*' "$work/stress.sbatch" | awk '{print $2}')
seed=$(grep -o -- '--seed [0-9]*' "$work/stress.sbatch" | awk '{print $2}')
shards=$(sed -n 's/^#SBATCH --array=0-\([0-9]*\)$/\1/p' "$work/stress.sbatch")
shards=$((shards + 1))
echo "recipe: $cases cases, seed $seed, $shards array tasks"

# Waits for a job (all tasks of an array) to end; prints nothing.
wait_ended() {
  local job=$1
  for ((i = 0; i < 1800; i++)); do
    if ! squeue -h -j "$job" 2>/dev/null | grep -q .; then return 0; fi
    sleep 1
  done
  fail "job $job did not end within 30 min"
}
# "STATE EXITCODE" of one job or array task.
job_state() {
  scontrol show job "$1" | awk '
    { for (i = 1; i <= NF; i++) { split($i, kv, "="); if (kv[1] == "JobState") s = kv[2]; if (kv[1] == "ExitCode") e = kv[2] } }
    END { print s, e }'
}
expect_state() {
  local job=$1 expected=$2 actual
  actual=$(job_state "$job")
  [[ $actual == "$expected" ]] || fail "job $job: expected '$expected', Slurm says '$actual'"
  echo "  job $job: $actual"
}
# The campaign's results without what depends on the machine (times, memory of the process).
verdict() {
  jq -S '{complete, partial, missing_cases, cases, seed, cases_run, failed_cases, failures_by_invariant,
          cases_by_family, worst_deviation,
          results: [.results[] | del(.seconds, .peak_rss_mib)]}' "$1"
}
expect_equal_campaigns() {
  verdict "$1" >"$work/left.json"
  verdict "$2" >"$work/right.json"
  diff -u "$work/left.json" "$work/right.json" >"$work/diff.txt" ||
    fail "$1 and $2 differ: $(head -40 "$work/diff.txt")"
  echo "  $1 equals $2 ($(jq .cases_run "$1") cases, $(jq .failed_cases "$1") failing)"
}
# Submits the docs' commands from directory $1; sets ARRAY_JOB_ID and MERGE_JOB_ID.
submit_recipe() {
  cd "$1"
  cp "$work/stress.sbatch" stress.sbatch
  # shellcheck disable=SC1091
  source "$work/submit.sh"
  [[ -n ${ARRAY_JOB_ID:-} && -n ${MERGE_JOB_ID:-} ]] || fail "the recipe's commands set no ARRAY_JOB_ID/MERGE_JOB_ID"
  cd "$work"
}
merge_again() { # directory, dependency list
  cd "$1"
  MERGE_JOB_ID=$(sbatch --parsable --dependency=afterany:"$2" --job-name=morphmill-merge --wrap \
    'morphmill stress-merge campaign/shard_* --out campaign/all')
  cd "$work"
}

# Seconds (one decimal) since a `date +%s%N` stamp.
seconds_since() { awk -v a="$1" -v b="$(date +%s%N)" 'BEGIN { printf "%.1f", (b - a) / 1e9 }'; }

echo "== single process"
single_start=$(date +%s%N)
status=0
morphmill stress --cases "$cases" --seed "$seed" --out "$work/single" >"$work/single.log" 2>&1 || status=$?
single_seconds=$(seconds_since "$single_start")
[[ $status -eq 0 ]] || fail "single-process run exited $status: $(tail -5 "$work/single.log")"
echo "  $cases cases in $single_seconds s (load average $(cut -d' ' -f1-3 /proc/loadavg))"

echo "== 1. the recipe as written"
mkdir -p "$work/recipe"
recipe_start=$(date +%s%N)
submit_recipe "$work/recipe"
wait_ended "$MERGE_JOB_ID"
recipe_seconds=$(seconds_since "$recipe_start")
for ((i = 0; i < shards; i++)); do expect_state "${ARRAY_JOB_ID}_$i" "COMPLETED 0:0"; done
expect_state "$MERGE_JOB_ID" "COMPLETED 0:0"
expect_equal_campaigns "$work/recipe/campaign/all/summary.json" "$work/single/summary.json"
echo "  $shards array tasks + merge, submission to merged: $recipe_seconds s (load average $(cut -d' ' -f1-3 /proc/loadavg))"

echo "== 2. a shard cancelled while running, one cancelled while pending; requeued and merged again"
mkdir -p "$work/cancel"
submit_recipe "$work/cancel"
last=$((shards - 1))
scancel "${ARRAY_JOB_ID}_$last" # pending: the tasks take both CPUs one at a time
shard0=$work/cancel/campaign/shard_0
for ((i = 0; i < 600; i++)); do
  [[ $(find "$shard0/cases" -name 'case_*.json' 2>/dev/null | wc -l) -ge 2 ]] && break
  sleep 0.5
done
scancel "${ARRAY_JOB_ID}_0" # running, two or more cases finished
wait_ended "$MERGE_JOB_ID"
expect_state "${ARRAY_JOB_ID}_0" "CANCELLED 4:0"
expect_state "$MERGE_JOB_ID" "FAILED 4:0"
merge_log=$work/cancel/slurm-$MERGE_JOB_ID.out
grep -q "shard $last/$shards missing" "$merge_log" || fail "the merge does not name shard $last/$shards: $(cat "$merge_log")"
grep -q "shard 0/$shards stopped (interrupted by SIGTERM)" "$merge_log" ||
  fail "the merge does not name shard 0/$shards as interrupted: $(cat "$merge_log")"
grep -q "incomplete campaign" "$merge_log" || fail "the merge does not refuse: $(cat "$merge_log")"
[[ ! -e $work/cancel/campaign/all ]] || fail "a refused merge left campaign/all"
echo "  merge refused: $(grep -m1 'incomplete campaign' "$merge_log")"
kept=$(find "$shard0/cases" -name 'case_*.json' | sort | head -n 1)
kept_stamp=$(stat -c %Y.%i "$kept")
grep -q '"complete": false' "$shard0/summary.json" || fail "shard 0's summary does not say it is incomplete"
scontrol requeue "${ARRAY_JOB_ID}_0"
scontrol update JobId="${ARRAY_JOB_ID}_0" StartTime=now
cd "$work/cancel"
NEW_JOB_ID=$(sbatch --parsable --array=$last stress.sbatch)
cd "$work"
merge_again "$work/cancel" "$ARRAY_JOB_ID:$NEW_JOB_ID"
wait_ended "$MERGE_JOB_ID"
expect_state "${ARRAY_JOB_ID}_0" "COMPLETED 0:0"
expect_state "${NEW_JOB_ID}_$last" "COMPLETED 0:0"
expect_state "$MERGE_JOB_ID" "COMPLETED 0:0"
[[ $(stat -c %Y.%i "$kept") == "$kept_stamp" ]] || fail "the requeued shard 0 ran $kept again instead of resuming"
echo "  the requeued shard resumed ($(basename "$kept") kept)"
expect_equal_campaigns "$work/cancel/campaign/all/summary.json" "$work/single/summary.json"

echo "== 3. a campaign whose cases fail"
mkdir -p "$work/failing"
sed -e 's/--cases [0-9]*/--cases 8/' -e 's/^exec morphmill stress /exec morphmill stress --reference-memory-cap 0.001 /' \
  "$work/stress.sbatch" >"$work/failing/stress.sbatch"
grep -q -- '--reference-memory-cap 0.001' "$work/failing/stress.sbatch" || fail "could not derive the failing script"
cd "$work/failing"
ARRAY_JOB_ID=$(sbatch --parsable stress.sbatch)
cd "$work"
merge_again "$work/failing" "$ARRAY_JOB_ID"
wait_ended "$MERGE_JOB_ID"
for ((i = 0; i < shards; i++)); do expect_state "${ARRAY_JOB_ID}_$i" "FAILED 1:0"; done
expect_state "$MERGE_JOB_ID" "FAILED 1:0"
summary=$work/failing/campaign/all/summary.json
[[ $(jq .complete "$summary") == true && $(jq .cases_run "$summary") == 8 && $(jq .failed_cases "$summary") == 8 ]] ||
  fail "the failing campaign's merged summary: complete $(jq .complete "$summary"), $(jq .cases_run "$summary") run, $(jq .failed_cases "$summary") failing (expected true, 8, 8)"
[[ $(jq '.failures_by_invariant.memory_bounded' "$summary") == 8 ]] || fail "expected memory_bounded on all 8 cases"
[[ $(find "$work/failing/campaign/all/failures" -name 'case_*.result.json' | wc -l) -eq 8 ]] ||
  fail "the merge did not copy the 8 failing jobs"
echo "  8 of 8 cases fail memory_bounded; summary complete, failing jobs copied"

echo "PASSED: recipe $recipe_seconds s as $shards array tasks, single process $single_seconds s ($cases cases)"
