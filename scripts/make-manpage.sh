#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Writes the morphmill(1) man page from the program's own help (`morphmill --help` and every
# `morphmill COMMAND --help`), so the page says what the installed program does. Run by the build
# (target morphmill_manpage); tested by tests/install/install_test.sh (man -l renders it).
# Usage: make-manpage.sh MORPHMILL_BINARY OUTPUT VERSION
set -euo pipefail
binary=$1 output=$2 version=$3

# troff-safe text: backslashes escaped, lines that would start a request made literal.
escape() { sed -e 's/\\/\\e/g' -e "s/^\\([.']\\)/\\\\\\&\\1/" -e 's/^-/\\-/'; }
# The help as a user sees it: "morphmill" rather than the build path; machine-specific defaults out.
help_of() {
  "$binary" "$@" --help | sed -e "s|^Usage: [^ ]*morphmill|Usage: morphmill|" \
                              -e 's/--memory-cap FLOAT=[0-9.]*/--memory-cap FLOAT/'
}

top=$(help_of)
# Command names: the lines of the Subcommands block that start with two spaces and a word.
mapfile -t commands < <(printf '%s\n' "$top" | sed -n '/^Subcommands:/,$p' | sed -n 's/^  \([a-z0-9-][a-z0-9-]*\) .*/\1/p')
if ((${#commands[@]} == 0)); then
  echo "make-manpage: no commands found in '$binary --help'" >&2
  exit 1
fi

tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
{
  echo ".TH MORPHMILL 1 \"\" \"morphmill $version\" \"User Commands\""
  echo ".SH NAME"
  echo "morphmill \\- compute what a milling tool leaves of a part, exactly, and measure how exact it is"
  echo ".SH SYNOPSIS"
  echo ".B morphmill"
  echo "[\\fB\\-\\-strict\\fR] \\fICOMMAND\\fR [\\fIOPTIONS\\fR] [\\fIARGUMENTS\\fR]"
  echo ".br"
  echo ".B morphmill"
  echo "\\fICOMMAND\\fR \\fB\\-\\-help\\fR"
  echo ".SH DESCRIPTION"
  echo "A part (the stock) is cut by a tool moving along ordered paths (G-code, polylines, CAMotics projects)."
  echo "MorphMill computes the regularized partial erosion \\(em the stock minus the tool-swept volume \\(em three"
  echo "independent ways (an exact surface generator, an OpenVDB level-set reference, exact sweep distances) and"
  echo "measures how far they are apart. Jobs are JSON files (see the job format in the documentation) or"
  echo "CAMotics projects; meshes are PLY, STL or OBJ."
  echo ".PP"
  echo "Global options:"
  echo ".nf"
  printf '%s\n' "$top" | sed -n '/^Options:/,/^$/p' | sed '1d' | escape
  echo ".fi"
  echo ".SH COMMANDS"
  for command in "${commands[@]}"; do
    echo ".SS $command"
    echo ".nf"
    help_of "$command" | escape
    echo ".fi"
  done
  echo ".SH EXIT STATUS"
  echo ".TP"; echo ".B 0"; echo "success: the result is what the command promises"
  echo ".TP"; echo ".B 1"; echo "a verdict that does not hold (verify, verify2d, compare, stress; erode when its surface is not a closed, oriented 2-manifold free of self-intersections)"
  echo ".TP"; echo ".B 2"; echo "bad input: the message names the file and the line or JSON path"
  echo ".TP"; echo ".B 3"; echo "internal error"
  echo ".TP"; echo ".B 4"; echo "an incomplete run (stress or study stopped by SIGINT/SIGTERM, stress-merge missing shards or cases)"
  echo ".SH EXAMPLES"
  echo ".nf"
  echo "morphmill info job.json"
  echo "morphmill verify job.json \\-o out/job"
  echo "morphmill erode job.json \\-o out/part.ply"
  echo "morphmill deviation out/part.ply out/ref.ply \\-\\-heatmap out/heat.ply"
  echo ".fi"
  echo ".SH LICENSE"
  echo "MorphMill's code is under the Apache License 2.0. The program also contains code of CGAL"
  echo "(LGPL\\-3.0\\-or\\-later); see NOTICE in the documentation directory."
  echo ".SH SEE ALSO"
  echo "The README and docs/ of the MorphMill sources: job format, G-code support, generator, reference, deviation, verify."
} > "$tmp"
mv "$tmp" "$output"
trap - EXIT
