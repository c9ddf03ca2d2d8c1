#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The command reference (docs/commands/) says what the program's --help says: regenerates it into a
# temporary directory and compares. On a difference, regenerate and commit:
#   bash scripts/make-command-docs.sh build/apps/morphmill
# Usage: command_reference_test.sh MORPHMILL_BINARY SOURCE_DIR
set -euo pipefail
binary=$1 source=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bash "$source/scripts/make-command-docs.sh" "$binary" "$tmp/commands"
if ! diff -ru "$source/docs/commands" "$tmp/commands"; then
  echo "docs/commands/ differs from the program's --help (above: - committed, + current)." >&2
  echo "Regenerate it: bash scripts/make-command-docs.sh $binary $source/docs/commands" >&2
  exit 1
fi
echo "docs/commands/: $(ls "$tmp/commands" | wc -l) pages match --help"
