#!/usr/bin/env bash
# make demo: runs the most complete real command on the bundled example.
set -euo pipefail
bin=${1:-build/apps/morphmill}
out=${2:-out/demo}
mkdir -p "$out"
"$bin" info data/jobs/slots.json
